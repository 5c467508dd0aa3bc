#!/usr/bin/env bash
# Issue 29's "every core, the same answer": the default 1-D sweep (Fig. 2,
# 1000 values of Omega, 500 + 100 periods each) and basins (Fig. 2's
# initial x2, v2 on a 200 x 200 grid, 100 + 20 periods) on 1, 2, 4, ...
# threads; not a test (it measures speed).  Made to be run in one call on
# a lent many-core machine with the build carried there:
#
#   bench/scaling.sh [-r ROUNDS] [-s STEPS] [-g GRID] BUILD [THREADS...]
#
# BUILD holds `vibroimpact`; THREADS default 1 2 4 ... up to nproc.  For
# each run: wall (best and median of ROUNDS, default 3, the thread counts
# interleaved), the process's CPU (user + sys, of the best run), the
# speed-up over one thread, the CPU inflation (CPU at T threads over CPU
# at one: above 1 is time lost inside the threads, which scheduling cannot
# explain) and whether the JSON equals the one-thread JSON byte for byte.
# Then two controls at the largest T: T one-thread basins processes at
# once (what the machine gives independent work: clock, memory, no shared
# address space) against one alone, and, where `perf stat` counts
# hardware events, cycles and instructions at 1 and T threads (the same
# instructions in more cycles: stalls or a lower clock; more
# instructions: spinning or repeated work).
set -euo pipefail
rounds=3 steps=1000 grid=200
while getopts r:s:g: o; do
  case $o in
    r) rounds=$OPTARG ;;
    s) steps=$OPTARG ;;
    g) grid=$OPTARG ;;
    *) echo "usage: $0 [-r ROUNDS] [-s STEPS] [-g GRID] BUILD [THREADS...]" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[ $# -ge 1 ] || { echo "usage: $0 [-r ROUNDS] [-s STEPS] [-g GRID] BUILD [THREADS...]" >&2; exit 2; }
app=$1/vibroimpact
shift
[ -x "$app" ] || { echo "$0: no $app" >&2; exit 2; }
threads=("$@")
if [ ${#threads[@]} -eq 0 ]; then
  for ((t = 1; t <= $(nproc); t *= 2)); do threads+=("$t"); done
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

sweep=(sweep --param forcing.omega --from 0.5 --to 1.8 --steps "$steps"
  --set run.method=exact --json --quiet)
basins=(basins --param 'initial.x[2]' --from -1 --to 0.09 --steps "$grid"
  --param2 'initial.v[2]' --from2 -1 --to2 1 --steps2 "$grid"
  --transient 100 --record 20 --set run.method=exact --json --quiet)

# one timed run: "wall cpu" appended to $tmp/NAME.T, the JSON kept per T
# (bash's own time: a lent machine may have no /usr/bin/time)
one() {
  local name=$1 t=$2 TIMEFORMAT='%R %U %S'
  shift 2
  { time "$app" "$@" --threads "$t" >"$tmp/$name.$t.json" 2>/dev/null; } 2>"$tmp/time"
  awk '{print $1, $2 + $3}' "$tmp/time" >>"$tmp/$name.$t"
}

for ((r = 0; r < rounds; r++)); do
  for t in "${threads[@]}"; do
    one sweep "$t" "${sweep[@]}"
    one basins "$t" "${basins[@]}"
  done
done

printf "%-7s %7s %8s %8s %9s %8s %9s %s\n" run threads best_s median_s cpu_s \
  speedup cpu_infl same_json
for name in sweep basins; do
  read -r w1 c1 <<<"$(sort -g "$tmp/$name.1" | head -1)"
  for t in "${threads[@]}"; do
    read -r wb cb <<<"$(sort -g "$tmp/$name.$t" | head -1)"
    wm=$(sort -g "$tmp/$name.$t" | awk '{a[NR] = $1} END{print a[int((NR + 1) / 2)]}')
    same=yes
    cmp -s "$tmp/$name.1.json" "$tmp/$name.$t.json" || same=NO
    awk -v n="$name" -v t="$t" -v wb="$wb" -v wm="$wm" -v cb="$cb" -v w1="$w1" \
      -v c1="$c1" -v s="$same" 'BEGIN{printf "%-7s %7d %8.3f %8.3f %9.2f %7.2fx %9.2f %s\n",
      n, t, wb, wm, cb, w1 / wb, cb / c1, s}'
  done
done

# controls at the largest thread count
T=${threads[-1]}
if [ "$T" -gt 1 ]; then
  s0=$(date +%s.%N)
  "$app" "${basins[@]}" --threads 1 >/dev/null 2>&1
  s1=$(date +%s.%N)
  for ((i = 0; i < T; i++)); do "$app" "${basins[@]}" --threads 1 >/dev/null 2>&1 & done
  wait
  s2=$(date +%s.%N)
  awk -v a="$s0" -v b="$s1" -v c="$s2" -v T="$T" 'BEGIN{printf "control: %d one-thread " \
    "basins processes at once %.3f s, one alone %.3f s (ratio %.2f)\n", T, c - b, b - a,
    (c - b) / (b - a)}'
  if perf stat -x, -e cycles,instructions true >/dev/null 2>"$tmp/perf" &&
     ! grep -q "not supported\|not counted" "$tmp/perf"; then
    for t in 1 "$T"; do
      perf stat -x, -e cycles,instructions,context-switches,cpu-migrations,page-faults \
        -o "$tmp/perf.$t" "$app" "${basins[@]}" --threads "$t" >/dev/null 2>&1
      awk -F, -v t="$t" '$3 ~ /^[a-z-]+$/ {v[$3] = $1} END{printf "perf basins, %d " \
        "threads: cycles %.4g instructions %.4g (IPC %.2f) context-switches %s " \
        "migrations %s page-faults %s\n", t, v["cycles"], v["instructions"],
        v["instructions"] / v["cycles"], v["context-switches"], v["cpu-migrations"],
        v["page-faults"]}' "$tmp/perf.$t"
    done
  else
    echo "perf: no hardware counters here"
  fi
fi
echo "($(nproc) cores: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//');" \
  "$(lscpu 2>/dev/null | awk -F: '/^Thread\(s\) per core/{gsub(/ /, "", $2); print $2}')" \
  "thread(s) per core; $rounds rounds; sweep $steps values, basins ${grid}x$grid)"
