#!/usr/bin/env bash
# `vibroimpact sweep --param model.chain.k|m|c` (structural keys, vi_param.h
# mass.scale, stiffness.scale, damping.scale): each value's point is the
# point of the scene built with that value (--set, the scene re-read): the
# same impacts, times and approach velocities to round-off, on the dense
# Fig. 2 chain, the Rayleigh-damped chain5 and a 300-mass band-stored chain
# (its modes are not computed: the band set-up is redone).  Keys a study
# cannot change are refused, naming the key.
#   sweep_structural_test.sh APP SRC DIR
set -u
app=$1 src=$2 dir=$3
py=/usr/bin/python3
scenes=$src/share/scenes
rm -rf "$dir" && mkdir -p "$dir"
fail=0
bad() { echo "FAIL: $*"; fail=1; }
# a band-stored chain: 1000 masses, Adams, no modes asked for
# (vi_scene_model.c's uses_band); its impacts come in the first periods
cat > "$dir/long.yaml" <<'Y'
name: long
model:
  chain: {n: 1000, m: 1.0, k: 1.0, c: 0.05}
forcing: {omega: 0.9, on: [1000], amplitude: 0.5}
stop: {mass: 1000, xs: 0.02, r: 0.7}
run: {rtol: 1.0e-9, atol: 1.0e-11, method: adams}
output: {impacts: true}
Y
# scene key value -> one point by --param, and one by --set (swept over
# the scene's own Omega, the 7th argument)
point() { # SCENE KEY VALUE OUT TRANSIENT RECORD OMEGA
  "$app" sweep "$1" --param "$2" --from "$3" --to "$3" --steps 1 --transient "$5" \
    --record "$6" --json > "$4.param.json" || bad "$1 --param $2 $3: exit $?"
  "$app" sweep "$1" --set "$2=$3" --param forcing.omega --from "$7" --to "$7" --steps 1 \
    --transient "$5" --record "$6" --json > "$4.set.json" || bad "$1 --set $2=$3: exit $?"
}
n=0
for v in 0.7 1.0 1.35; do point "$scenes/fig2.yaml" model.chain.k $v "$dir/k$v" 40 8 0.9; n=$((n+1)); done
for v in 0.6 1.5; do point "$scenes/fig2.yaml" model.chain.m $v "$dir/m$v" 40 8 0.9; done
for v in 0.0 0.25; do point "$scenes/fig2.yaml" model.chain.c $v "$dir/c$v" 40 8 0.9; done
for v in 0.8 1.3; do point "$scenes/chain5.yaml" model.chain.k $v "$dir/r$v" 40 8 0.5; done
point "$dir/long.yaml" model.chain.k 1.2 "$dir/long" 0 3 0.9
$py - "$dir" <<'PY' || bad "points differ"
import glob, json, sys
pairs = sorted(glob.glob(sys.argv[1] + "/*.param.json"))
assert len(pairs) == 10, pairs
for p in pairs:
    a = json.load(open(p))
    b = json.load(open(p.replace(".param.", ".set.")))
    assert a["n"] == b["n"] and a["m"] == b["m"], (p, a["n"], b["n"])
    va, vb = a["vn"][0], b["vn"][0]
    assert len(va) == len(vb) > 0, (p, len(va), len(vb))
    ta, tb = a["impact_time_mod_T"][0], b["impact_time_mod_T"][0]
    # the same model: round-off only (the band chain integrates with
    # CVODE, whose steps see the same numbers)
    err = max(max(abs(x - y) for x, y in zip(va, vb)), max(abs(x - y) for x, y in zip(ta, tb)))
    assert err <= 1e-9, (p, err)
    print("%-12s %3d impacts, largest difference %.1e" % (p.split("/")[-1][:-11], len(va), err))
PY
# a sweep across k: the points change with k (a different orbit at each)
"$app" sweep "$scenes/fig2.yaml" --param model.chain.k --from 0.8 --to 1.2 --steps 3 \
  --transient 40 --record 8 --json > "$dir/sweep.json" || bad "sweep exit $?"
$py - "$dir/sweep.json" <<'PY' || bad "sweep across k"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["key"] == "model.chain.k" and len(j["vn"]) == 3
assert len({round(v[-1], 6) for v in j["vn"]}) == 3, j["vn"]
PY
# refused: the chain's size, Rayleigh-replaced damping, a non-chain scene
"$app" sweep "$scenes/fig2.yaml" --param model.chain.n --from 2 --to 3 --steps 2 \
  > /dev/null 2> "$dir/err1" && bad "model.chain.n accepted"
grep -q "model.chain.n" "$dir/err1" || bad "model.chain.n: $(cat "$dir/err1")"
"$app" sweep "$scenes/nonproportional.yaml" --param model.chain.k --from 1 --to 2 --steps 2 \
  > /dev/null 2> "$dir/err2" && bad "model.chain.k on an explicit model accepted"
grep -q "chain" "$dir/err2" || bad "nonproportional: $(cat "$dir/err2")"
[ $fail -eq 0 ] && echo "1 passed, 0 failed"
exit $fail
