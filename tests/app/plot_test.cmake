# Make every figure from runs of the default scene (two masses), of
# chatter.yaml (one mass: 1-D or [T][1] datasets) and of duffing.yaml (the
# ledger's nonlinear-force column NE), the restitution chart of
# an `energy -o` file, and check what the figures draw (plot_check.py).
file(REMOVE_RECURSE "${DIR}")
file(MAKE_DIRECTORY "${DIR}")
get_filename_component(SHARE "${SCRIPT}" DIRECTORY)
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endfunction()
run("${APP}" --periods 30 --quiet -o "${DIR}/fig2.h5")
run("${APP}" "${SHARE}/scenes/chatter.yaml" --periods 10 --quiet -o "${DIR}/chatter.h5")
run("${APP}" "${SHARE}/scenes/duffing.yaml" --periods 20 --quiet -o "${DIR}/duffing.h5")
run("${APP}" energy -o "${DIR}/orbit.h5")
# a transient without forcing (a ball thrown off the stop that sticks):
# sampled and drawn whole, and a --from/--to window of the forced run
file(WRITE "${DIR}/ball.yaml" "name: ball\nmodel: {M: [[1.0]], K: [[0.0]]}\n"
  "forcing: {f0: [1.0]}\nstop: {mass: 1, xs: 0.0, r: 0.8}\n"
  "initial: {x: [0.0], v: [-1.0]}\nrun: {t_end: 20}\n"
  "output: {samples_per_period: 50, ledger: true}\n")
run("${APP}" "${DIR}/ball.yaml" --quiet -o "${DIR}/ball.h5")
# every figure drawn in one Python process (matplotlib imported once: seven
# interpreters spent most of this test's time importing it)
file(MAKE_DIRECTORY "${DIR}/window")
file(WRITE "${DIR}/plot_all.py" "
import sys
sys.path.insert(0, '${SHARE}')
import plot
for stem in ('fig2', 'chatter', 'duffing', 'orbit', 'ball'):
    if plot.main(['${DIR}/' + stem + '.h5', '--out', '${DIR}']):
        sys.exit('plot.py failed on ' + stem)
if plot.main(['${DIR}/fig2.h5', '--from', '100', '--to', '120', '--out', '${DIR}/window']):
    sys.exit('plot.py failed on the window')
try:
    plot.main(['${DIR}/fig2.h5', '--from', '3', '--out', '${DIR}/window'])
    sys.exit('--from without --to was accepted')
except SystemExit as e:
    if e.code in (0, None):
        sys.exit('--from without --to was accepted')
")
run(/usr/bin/python3 "${DIR}/plot_all.py")
foreach(f fig2_phase fig2_gap fig2_ledger fig2_restitution chatter_phase chatter_gap
          chatter_ledger duffing_ledger orbit_restitution ball_phase ball_gap
          ball_ledger window/fig2_gap window/fig2_phase)
  if(NOT EXISTS "${DIR}/${f}.png")
    message(FATAL_ERROR "missing ${f}.png")
  endif()
  file(SIZE "${DIR}/${f}.png" size)
  if(size LESS 10000)
    message(FATAL_ERROR "${f}.png is only ${size} bytes")
  endif()
endforeach()

# What the figures draw, checked on the data plot.py plots:
# - the phase portrait's series holds each impact of its window twice, at
#   the impact time, before (v_minus) then after (v_plus), on the stop:
#   w.x = x_s to the event location's accuracy (1e-7 at rtol 1e-8);
# - the restitution chart marks the orbit's (RE, KE_i), and the r it
#   recovers by WB 12 is the model's r = 0.7 (energy balance, 1e-6).
file(WRITE "${DIR}/plot_check.py" "
import sys
import h5py
import numpy as np
sys.path.insert(0, '${SHARE}')
import plot
bad = 0
for stem in ('fig2', 'chatter'):
    f = h5py.File('${DIR}/' + stem + '.h5', 'r')
    t, x, v, q, qd = plot.samples(f['trajectory'], 0)
    tt, xx, vv, qq, qqd = plot.with_impacts(f, t, x, v, q, qd)
    w, xs = np.ravel(f['model/w'][:]), f['model'].attrs['x_s']
    ti = f['impacts/time'][:]
    inside = (ti >= t[0]) & (ti <= t[-1])
    ti = ti[inside]
    vm, vp = plot.rows(f['impacts/v_minus'])[inside], plot.rows(f['impacts/v_plus'])[inside]
    ok = len(tt) == len(t) + 2 * len(ti) and np.all(np.diff(tt) >= 0)
    for i in range(len(ti)):
        k = np.flatnonzero(tt == ti[i])
        k = k[-2:]  # a sample at the impact time comes first
        ok &= len(k) == 2 and k[1] == k[0] + 1
        ok &= np.allclose(vv[k[0]], vm[i], 0, 0) and np.allclose(vv[k[1]], vp[i], 0, 0)
        ok &= bool(np.all(np.abs(xx[k] @ w - xs) < 1e-7))
        ok &= np.allclose(qq[k[0]], qq[k[1]], 0, 1e-12)  # positions do not jump
    print(stem, 'n =', x.shape[1], ':', len(t), 'samples,', len(ti), 'impacts merged:', 'ok' if ok else 'FAIL')
    bad += not ok
f = h5py.File('${DIR}/orbit.h5', 'r')
run = plot.restitution(f, '${DIR}/orbit_check.png')
r = f['model'].attrs['r']
ok = run is not None and abs(run[2] - r) < 1e-6 and 0 < run[0] < run[1]
print('restitution chart marks RE, KE_i, r =', run, 'ok' if ok else 'FAIL')
bad += not ok
# the windows: a transient whole (the ball's impacts end at t = 10 and the
# rest sticks: a last fifth would be a flat line), --from/--to exactly
f = h5py.File('${DIR}/ball.h5', 'r')
tr = f['trajectory']
k0, k1 = plot.window(tr, ('last', 1.0))
ok = k0 == 0 and k1 == tr['time'].shape[0] and tr['time'][k1 - 1] >= 19.9
f = h5py.File('${DIR}/fig2.h5', 'r')
tr = f['trajectory']
k0, k1 = plot.window(tr, ('time', 100.0, 120.0))
t = tr['time'][k0:k1]
ok &= bool(t[0] >= 100 and t[-1] <= 120 and tr['time'][k0 - 1] < 100 and tr['time'][k1] > 120)
print('plot windows: whole transient, --from/--to:', 'ok' if ok else 'FAIL')
bad += not ok
sys.exit(bad)
")
run(/usr/bin/python3 "${DIR}/plot_check.py")
message(STATUS "figures and their data checked in ${DIR}")
