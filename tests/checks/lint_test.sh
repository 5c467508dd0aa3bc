#!/usr/bin/env bash
# Static analysis: clang-tidy (checks in .clang-tidy) and cppcheck
# (warning, performance, portability) over the files known to be clean, so
# that they stay clean.  Findings are reported per file.
#   lint_test.sh SRC BUILD            the files listed below
#   lint_test.sh SRC BUILD --all      every C file of the build, to see what
#                                     remains (not a pass/fail criterion)
# BUILD must have compile_commands.json (CMAKE_EXPORT_COMPILE_COMMANDS, on
# by default).  Exits 77 (ctest: skipped) if clang-tidy or cppcheck is
# missing (Debian packages clang-tidy, cppcheck).  The files are checked
# VI_LINT_JOBS at a time (default: every core), each file's report printed
# in the order of the list.  Clean files are remembered by content (see
# VI_LINT_CACHE below): a second run checks only what changed.
set -uo pipefail
src=$(cd "$1" && pwd) build=$(cd "$2" && pwd)

# The files kept clean; add a file here once it is (run with --all to see).
files=(
  src/base/vi_status.c src/base/vi_version.c src/model/vi_model.c src/model/vi_modal.c
  src/impact/vi_impact.c src/model/vi_builders.c src/ledger/vi_ledger.c src/sim/vi_nvector.c src/base/vi_dense.c
  src/base/vi_minimize.c
  src/sim/vi_force.c src/orbit/vi_orbit_pnm.c src/io/vi_scene_edit.c src/impact/vi_contact.c
  src/sim/vi_sim.c src/sim/vi_sim_io.c src/sim/vi_chatter.c src/sim/vi_cvode.c src/sim/vi_arkode.c src/sim/vi_rhs.c
  src/io/vi_output.c src/model/vi_range.c src/io/vi_mmio.c tests/io/test_mmio.c apps/vi_cmd_truncation.c
  src/fortran/vi_gen_constants.c tests/fortran/test_fortran_compare.c
  src/orbit/vi_orbit.c src/orbit/vi_classify.c src/orbit/vi_balance.c src/orbit/vi_orbit_var.c
  src/sim/vi_exact.c src/sim/vi_exact_scan.c src/flow/vi_flow.c src/flow/vi_general.c
  tests/sim/test_exact_stops.c
  tests/api/test_api.c tests/sim/test_sim.c tests/ledger/test_ledger.c tests/model/test_model.c
  tests/sim/test_stops.c
  tests/model/test_modal.c tests/impact/test_impact.c tests/sim/test_force.c tests/api/test_misuse.c
  tests/io/test_misuse_io.c
  tests/vi_testutil.c tests/sim/test_arkode.c tests/sim/test_exact.c tests/orbit/test_orbit.c
  tests/io/test_scene_edit.c tests/io/test_writer.c tests/io/test_fe_scene.c tests/faults/test_faults.c
  tests/faults/vi_enospc.c tests/stress/stress_util.c tests/stress/test_stress_chatter.c
  tests/stress/test_stress_floors.c tests/stress/test_stress_graze.c
  tests/stress/test_stress_mdof.c tests/stress/test_stress_soft.c
  tests/stress/test_stress_start.c tests/stress/test_stress_chain.c
  tests/stress/test_stress_energy.c tests/stress/test_stress_stops.c
  tests/stress/test_stress_chatref.c tests/stress/test_stress_cancel.c
  tests/stress/test_stress_scale.c
  apps/vi_app_h5.c apps/vi_cmd_orbits.c
  apps/vi_cmd_orbits_cont.c apps/vi_diagram_file.c apps/vi_diagram_main.c bench/vi_bench_sweep.c
  src/study/vi_curve.c apps/vi_cmd_curves.c apps/vi_curves_h5.c tests/study/test_curve.c
  bench/vi_bench_curves.c
  src/io/vi_scene.c src/io/vi_scene_model.c src/io/vi_scene_options.c
  src/io/vi_writer.c apps/vibroimpact.c apps/vi_cmd_run.c apps/vi_cmd_energy.c
  src/sim/vi_band.c src/model/vi_band_model.c tests/sim/test_band.c bench/vi_bench_band.c
  src/model/vi_forcing.c src/model/vi_dense_model.c src/sim/vi_sim_state.c src/sim/vi_grid.c
  tests/app/test_app.c tests/flow/test_flow.c tests/io/test_scene.c tests/app/test_sweep_app.c tests/study/test_sweep.c
  src/flow/vi_constrained.c src/sim/vi_held.c tests/stress/test_stress_held.c
  tests/app/test_app.c tests/flow/test_flow.c tests/io/test_scene.c tests/study/test_sweep.c
  bench/vi_bench.c apps/vi_cmd_sweep.c apps/vi_app_scene.c bench/vi_bench_chatter.c
  src/model/vi_param.c tests/model/test_param.c
  src/study/vi_identify.c src/io/vi_identify_h5.c apps/vi_cmd_identify.c
  src/study/vi_identify_fit.c src/study/vi_identify_global.c src/study/vi_identify_resid.c
  src/study/vi_identify_seed.c src/study/vi_identify_stats.c src/study/vi_identify_scan2.c
  src/study/vi_identify_track.c
  src/io/vi_truncation_h5.c src/io/vi_h5_util.c src/io/vi_diagram_h5.c
  src/study/vi_truncation.c tests/study/test_truncation.c
  tests/study/test_identify.c bench/vi_bench_identify.c
  src/orbit/vi_lyapunov.c tests/orbit/test_lyapunov.c
  src/orbit/vi_census.c tests/orbit/test_census.c
  src/model/vi_param.c tests/model/test_param.c src/study/vi_sweep.c tests/model/test_param_modes.c
  src/model/vi_truncate.c tests/model/test_truncate.c
  src/study/vi_cont.c tests/study/test_cont.c tests/study/test_basins.c src/io/vi_scene_param.c
  src/model/vi_sparse.c src/model/vi_eigs.c tests/model/test_sparse.c
  tests/model/test_arpack_words.c
  bench/vi_bench_sparse.c examples/c/fe_host.c
  tests/io/vi_io_testutil.c
  src/io/vi_hbio.c src/io/vi_coordio.c src/io/vi_matrix.c tests/io/test_hbio.c
  apps/vi_app_fe.c tests/model/test_fe_struct.c tests/model/test_fe_published.c
  tests/io/test_fe_whole.c tests/io/vi_mm_testutil.c
  tests/orbit/test_orbits.c bench/vi_bench_bar.c
  src/sim/vi_quadmap.c tests/sim/test_quadmap.c
  src/ledger/vi_ledger_flight.c tests/ledger/test_ledger_flight.c
  tests/flow/test_xseg_run.c
)
# Headers whose findings count (a finding in another header is silent until
# the header joins this list): a regex for clang-tidy's --header-filter.
headers='(include/vibroimpact/[^/]*|src/[a-z]+/vi_[a-z_]*internal|src/orbit/vi_orbit_handle|src/sim/vi_rhs|src/sim/vi_sim_state|src/sim/vi_grid|src/sim/vi_quadmap|src/ledger/vi_ledger_flight|src/model/vi_forcing|src/model/vi_storage|src/io/vi_h5_util|src/io/vi_diagram_h5|apps/vi_app|tests/io/vi_io_testutil)\.h$'

# The path-sensitive analyser explores each function until it has built
# max-nodes states of its exploded graph.  clang's default (225 000, "deep")
# costs 3-5 s in each of the ~80 functions that reach it, 85 % of the lint's
# time; 75 000 (clang's "shallow" budget, inlining kept at the deep mode's
# limits, unlike mode=shallow) cuts those to a third.  Every function that
# ends below it, i.e. all but those ~80, is explored exactly as before.
# VI_LINT_MAX_NODES=225000 restores the default.
max_nodes=${VI_LINT_MAX_NODES:-75000}

for tool in clang-tidy cppcheck; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIP: $tool not found (apt-get install clang-tidy cppcheck)"; exit 77
  fi
done
db=$build/compile_commands.json
if [ ! -f "$db" ]; then
  echo "FAIL: $db missing: configure with -DCMAKE_EXPORT_COMPILE_COMMANDS=ON"; exit 1
fi
if [ "${3:-}" = --all ]; then
  mapfile -t files < <(sed -n 's|.*"file": "'"$src"'/\(.*\.c\)".*|\1|p' "$db" \
                       | grep -v "^${build#"$src"/}/" | sort -u)
  headers='(include|src|apps|bench)/.*\.h$'
fi

# The test files are analysed with cmocka_analyzer.h force-included:
# there a failed assertion ends the test (the header says why).  Only the
# analysis sees it; the tests are compiled as they are.
cmocka_h=$src/tests/checks/cmocka_analyzer.h

# A clean file is remembered (like ccache): its key hashes the file, its
# compile command (paths relative to the checkout), the headers its
# compilation read (make's depfile or Ninja's deps log: the project's by
# content, the system's by path, size and time), the tools' versions,
# .clang-tidy and this script; an unchanged file is not analysed again, and
# a changed header sends back only the files that include it.  Without
# either (another generator) every header of the project counts.  Files
# with findings are never cached.  VI_LINT_CACHE=off turns it off;
# VI_LINT_CACHE_DIR moves it (default ~/.cache/vibroimpact/lint).
cache=""
if [ "${VI_LINT_CACHE:-on}" != off ]; then
  cache=${VI_LINT_CACHE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/vibroimpact/lint}
  mkdir -p "$cache" 2>/dev/null || cache=""
fi
common=$( { clang-tidy --version; cppcheck --version
            cat "$src/.clang-tidy" "$src/tests/checks/lint_test.sh" "$cmocka_h"
            echo "$headers $max_nodes"; } | sha256sum | cut -c1-64)
all_headers=$(find "$src/src" "$src/include" "$src/apps" "$src/tests" "$src/bench" \
                   "$src/examples" "$build/include" -name '*.h' 2>/dev/null | sort |
                xargs cat | sha256sum | cut -c1-64)

# The headers file $1's compilation read, as one digest (see above).
header_digest() {
  local entry dir obj dep
  entry=$(grep -B2 "\"file\": \"$src/$1\"" "$db" | head -2)
  dir=$(sed -n 's/.*"directory": "\(.*\)",$/\1/p' <<< "$entry")
  obj=$(sed -n 's/.* -o \([^ ]*\) .*/\1/p' <<< "$entry")
  dep=$dir/$obj.d
  local list
  if [ -n "$obj" ] && [ -f "$dep" ]; then      # make keeps the depfile
    list=$(sed 's/^[^:]*://; s/\\$//' "$dep" | tr ' ' '\n')
  elif [ -n "$obj" ] && [ -f "$dir/build.ninja" ]; then  # ninja keeps its log
    list=$(ninja -C "$dir" -t deps "$obj" 2>/dev/null | grep '^    ' | tr -d ' ' |
           sed "s|^\([^/]\)|$dir/\1|")
  fi
  if ! grep -q '\.h$' <<< "${list:-}"; then
    echo "all $all_headers"
    return
  fi
  local h sys=() own=()
  while read -r h; do
    case $h in /usr/*) sys+=("$h") ;; *) own+=("$h") ;; esac
  done < <(grep '\.h$' <<< "$list" | sort -u)
  { [ ${#sys[@]} -eq 0 ] || stat -c '%n %s %Y' "${sys[@]}"
    [ ${#own[@]} -eq 0 ] || sha256sum "${own[@]}" | sed "s|$build|BUILD|; s|$src|SRC|"
  } | sha256sum | cut -c1-64
}

# One file: its report into $tmp/N.out, its finding count into $tmp/N.n.
lint_one() {
  local i=$1 f=$2 nt nc t0=${EPOCHREALTIME/[.,]/} key=""
  if [ -n "$cache" ]; then
    # the command with the checkout's and the build's paths taken out: a
    # clone elsewhere (CI's) finds what an earlier clone checked
    key=$( { echo "$common"; grep -B1 "\"file\": \"$src/$f\"" "$db" | head -1 |
               sed "s|$build|BUILD|g; s|$src|SRC|g"
             header_digest "$f"; cat "$f"; } | sha256sum | cut -c1-64)
    if [ -f "$cache/$key" ]; then
      echo "ok   $f (unchanged since a clean check)" > "$tmp/$i.out"
      echo 0 > "$tmp/$i.n"
      return
    fi
  fi
  local shim=()
  case $f in tests/*) shim=(--extra-arg=-include --extra-arg="$cmocka_h") ;; esac
  clang-tidy -p "$build" --quiet --header-filter="$headers" --extra-arg=-Xclang \
    --extra-arg=-analyzer-config --extra-arg=-Xclang --extra-arg=max-nodes="$max_nodes" \
    "${shim[@]}" "$f" > "$tmp/$i.tidy" 2> /dev/null
  # the filter must be the path as the database spells it (absolute): a
  # relative one matches nothing, and cppcheck then checks nothing, says so
  # on stdout and exits 1 -- which is why its status is read
  if ! cppcheck --project="$db" --file-filter="$src/$f" --enable=warning,performance,portability \
       --inline-suppr --quiet --template='{file}:{line}:{column}: {severity}: {message} [{id}]' \
       2> "$tmp/$i.cpp" > "$tmp/$i.cppout"; then
    sed "s|^|$f: error: cppcheck did not check it: |" "$tmp/$i.cppout" >> "$tmp/$i.cpp"
    grep -q . "$tmp/$i.cppout" || echo "$f: error: cppcheck failed" >> "$tmp/$i.cpp"
  fi
  # VI_LINT_TIMES=FILE: seconds per file (wall), to find the slow ones
  [ -n "${VI_LINT_TIMES:-}" ] &&
    echo "$(( (${EPOCHREALTIME/[.,]/} - t0) / 1000 )) ms $f" >> "$VI_LINT_TIMES"
  nt=$(grep -cE ': (warning|error): ' "$tmp/$i.tidy")
  nc=$(grep -cE ': (warning|error|performance|portability|style): ' "$tmp/$i.cpp")
  echo $((nt + nc)) > "$tmp/$i.n"
  [ -n "$key" ] && [ $((nt + nc)) -eq 0 ] && touch "$cache/$key"
  if [ $((nt + nc)) -gt 0 ]; then
    echo "FAIL $f: $nt clang-tidy, $nc cppcheck"
    grep -E ': (warning|error): ' "$tmp/$i.tidy" | sed "s|^$src/||; s|^|  |"
    sed "s|^$src/||; s|^|  |" "$tmp/$i.cpp"
  else
    echo "ok   $f"
  fi > "$tmp/$i.out"
}

cd "$src"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# a file listed twice is checked once
mapfile -t files < <(printf '%s\n' "${files[@]}" | awk '!seen[$0]++')
export -f lint_one
export src build db headers tmp cache common all_headers max_nodes cmocka_h
export -f header_digest
jobs=${VI_LINT_JOBS:-$(nproc)}
# the largest files first (the analyser's time grows with a file's size):
# a large file started last would leave the other cores idle at the end
for i in "${!files[@]}"; do
  printf '%s %s %s\n' "$(wc -c < "${files[$i]}")" "$i" "${files[$i]}"
done | sort -rn | cut -d' ' -f2- |
  xargs -P "$jobs" -L 1 bash -c 'lint_one "$1" "$2"' lint_one
bad=0 total=0
for i in "${!files[@]}"; do
  if [ ! -f "$tmp/$i.n" ]; then
    echo "FAIL ${files[$i]}: not checked"; bad=$((bad + 1)); continue
  fi
  cat "$tmp/$i.out"
  n=$(cat "$tmp/$i.n")
  total=$((total + n))
  [ "$n" -gt 0 ] && bad=$((bad + 1))
done
echo "$((${#files[@]} - bad)) of ${#files[@]} files clean, $total findings"
[ $bad -eq 0 ]
