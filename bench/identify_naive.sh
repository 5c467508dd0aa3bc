#!/usr/bin/env bash
# Identification from naive guesses, counted over noise seeds: the 4-mode
# beam's restitution and base amplitude (share/scenes/cantilever4.yaml;
# truth r = 0.75, base 0.01) fitted to SciPy's recording of it
# (tests/study/data/beam4.csv: DOP853 with the impact law, not our code),
# 10 periods at 0.1 % noise, from bases 0.2 to 5 times the truth; then
# the forcing frequency too (truth 0.85, from 0.85 and 1.3) on its tip
# acceleration (beam4_acc_rate.csv: 20 periods at 61.3 samples each,
# 0.1 % noise), seeds 1..2 (its fits take longer).  A fit
# is right when both lie within 4 standard errors of the truth (seed 7's
# base lies 3.1 from it at the best minimum: 3 would call 1 seed in 8
# wrong whatever the start); the wrong ones are listed with the r and
# orbit they ended on.  Not a test: it
# counts and times.
#
#   bench/identify_naive.sh [-s SEEDS] BUILD [BUILD...]
#
# BUILD holds `vibroimpact`; SEEDS (default 8) noise seeds 1..SEEDS; each
# build's fits in turn, their CPU time from bash's times.
set -euo pipefail
seeds=8
while getopts s: o; do
  case $o in
    s) seeds=$OPTARG ;;
    *) echo "usage: $0 [-s SEEDS] BUILD [BUILD...]" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[ $# -ge 1 ] || { echo "usage: $0 [-s SEEDS] BUILD [BUILD...]" >&2; exit 2; }
src=$(cd "$(dirname "$0")/.." && pwd)
py=/usr/bin/python3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for ((s = 1; s <= seeds; s++)); do
  $py "$src/tests/study/noisy_recording.py" "$src/tests/study/data/beam4.csv" 10 0.001 "$s" \
    > "$tmp/rec$s.csv"
done
for s in 1 2; do
  $py - "$src/tests/study/data/beam4_acc_rate.csv" "$s" > "$tmp/acc$s.csv" <<'PY'
import sys
import numpy as np
d = np.loadtxt(sys.argv[1], delimiter=",", comments="#", skiprows=3)
a = d[:, 3] + 0.001 * np.ptp(d[:, 3]) * np.random.default_rng(int(sys.argv[2])).standard_normal(len(d))
print("t,a")
for t, y in zip(d[:, 0], a):
    print("%.17g,%.17g" % (t, y))
PY
done
judge='
import json, sys
try:
    j = json.load(sys.stdin)
    r, b = j["fit"]["stop.r"], j["fit"]["forcing.base"]
    ok = abs(r["value"] - 0.75) < 4 * r["stderr"] and abs(b["value"] - 0.01) < 4 * b["stderr"]
    w = j["fit"].get("forcing.omega")
    ok = ok and (w is None or abs(w["value"] - 0.85) < 4 * w["stderr"])
    print(int(ok), "r=%.4f,P(%d,%d)" % (r["value"], j["orbit"]["n"], j["orbit"]["m"]))
except Exception:
    print(0, "failed")'
for b in "$@"; do
  ok=0 n=0 bad=""
  t0=$(awk '{print $14 + $15 + $16 + $17}' /proc/$$/stat)
  for ((s = 1; s <= seeds; s++)); do
    for g in 0.002 0.003 0.005 0.02 0.03 0.05; do
      read -r good what < <("$b/vibroimpact" identify "$src/share/scenes/cantilever4.yaml" \
        --data "$tmp/rec$s.csv" --fit stop.r,forcing.base --set forcing.base=$g --json \
        2>/dev/null | $py -c "$judge")
      n=$((n + 1))
      if [ "$good" = 1 ]; then ok=$((ok + 1)); else bad="$bad seed $s from $g: $what;"; fi
    done
  done
  t1=$(awk '{print $14 + $15 + $16 + $17}' /proc/$$/stat)
  echo "$b: r, base: $ok of $n right, $(awk -v a="$t0" -v c="$t1" -v h="$(getconf CLK_TCK)" \
    'BEGIN{printf "%.1f", (c - a) / h}') CPU-s;${bad:- none wrong}"
  ok=0 n=0 bad=""
  for s in 1 2; do
    for g in 0.002 0.003 0.005 0.02 0.03 0.05; do
      for w in 0.85 1.3; do
        read -r good what < <("$b/vibroimpact" identify "$src/share/scenes/cantilever4.yaml" \
          --data "$tmp/acc$s.csv" --fit forcing.omega,stop.r,forcing.base \
          --set forcing.base=$g --set forcing.omega=$w --json 2>/dev/null | $py -c "$judge")
        n=$((n + 1))
        if [ "$good" = 1 ]; then ok=$((ok + 1)); else bad="$bad seed $s from $g, $w: $what;"; fi
      done
    done
  done
  t2=$(awk '{print $14 + $15 + $16 + $17}' /proc/$$/stat)
  echo "$b: Omega, r, base from the accelerometer: $ok of $n right, $(awk -v a="$t1" \
    -v c="$t2" -v h="$(getconf CLK_TCK)" 'BEGIN{printf "%.1f", (c - a) / h}') CPU-s;${bad:- none wrong}"
done
