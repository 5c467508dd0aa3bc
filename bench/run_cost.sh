#!/usr/bin/env bash
# The program's `cost` line against the loop alone (issue 29, "a run starts
# at once"); not a test: it measures speed, which a shared machine cannot
# judge pass/fail.
#
#   bench/run_cost.sh [-n N] [-p PERIODS] [-l ROUNDS] BUILD [BUILD...]
#
# For each BUILD (a build directory holding `vibroimpact` and `vi_bench`):
# N runs of `vibroimpact run --method exact --periods PERIODS` on the
# default scene (Fig. 2, the ledger on) and N with the ledger off
# (`--set output.ledger=false`), every build's runs interleaved, each a
# fresh process; then `vi_bench PERIODS 20 limit` ROUNDS times for each
# build, interleaved, whose exact-method loop (the best of all) is the loop
# alone.  Prints best and median of the
# `cost` lines (the time inside vi_sim_run), of `set-up` (vi_sim_setup
# before it, where the program prints one) and of set-up + cost, and the
# ratios to the loop (cost's best and median, the sum's best); then
# `vi_bench PERIODS 20 setup` (the first set-up of a process against later
# ones, with their page faults).  Defaults:
# N = 30, PERIODS = 100, ROUNDS = 4.
set -euo pipefail
n=30 periods=100 rounds=4
while getopts n:p:l: o; do
  case $o in
    n) n=$OPTARG ;;
    p) periods=$OPTARG ;;
    l) rounds=$OPTARG ;;
    *) echo "usage: $0 [-n N] [-p PERIODS] [-l ROUNDS] BUILD [BUILD...]" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[ $# -ge 1 ] || { echo "usage: $0 [-n N] [-p PERIODS] [-l ROUNDS] BUILD [BUILD...]" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# one run: "cost set-up" in ms (set-up 0 where the program has no such line)
one() {
  "$1/vibroimpact" run --method exact --periods "$periods" "${@:2}" |
    awk '/^  cost /{c = $2} /^  set-up /{s = $2} END{print c, (s == "" ? 0 : s)}'
}

for ((i = 0; i < n; i++)); do
  for b in "$@"; do
    k=$(echo "$b" | tr / _)
    one "$b" >>"$tmp/$k.on"
    one "$b" --set output.ledger=false >>"$tmp/$k.off"
  done
done

# the loop alone: vi_bench's best of 5, `rounds` times for each build,
# interleaved
for ((r = 0; r < rounds; r++)); do
  for b in "$@"; do
    "$b/vi_bench" "$periods" 20 limit | awk '$1 == "fig2" {print $2}' \
      >>"$tmp/$(echo "$b" | tr / _).loop"
  done
done

# best and median of column c of a file, and of the sum of both columns
stats() {
  awk -v c="$2" '{print (c == 3 ? $1 + $2 : $c)}' "$1" | sort -g |
    awk '{a[NR] = $1} END{printf "%.3f %.3f", a[1], a[int((NR + 1) / 2)]}'
}

printf "%-28s %-9s %15s %15s %15s %9s %13s %8s\n" build ledger "cost best/med" \
  "set-up best/med" "sum best/med" loop_ms "cost/loop" sum/loop
for b in "$@"; do
  k=$(echo "$b" | tr / _)
  loop=$(sort -g "$tmp/$k.loop" | head -1)
  for l in on off; do
    read -r cb cm <<<"$(stats "$tmp/$k.$l" 1)"
    read -r sb sm <<<"$(stats "$tmp/$k.$l" 2)"
    read -r tb tm <<<"$(stats "$tmp/$k.$l" 3)"
    awk -v b="$b" -v l="$l" -v cb="$cb" -v cm="$cm" -v sb="$sb" -v sm="$sm" \
      -v tb="$tb" -v tm="$tm" -v loop="$loop" 'BEGIN{
      printf "%-28s %-9s %7s %7s %7s %7s %7s %7s %9.4f %6.2f %6.2f %8.2f\n", b, l,
        cb, cm, sb, sm, tb, tm, loop, cb / loop, cm / loop, tb / loop}'
  done
done
# the set-up in a process's first sim against later ones (vi_bench setup):
# what is first touch, paid once a process, and what a set-up costs
for b in "$@"; do
  echo "$b: $("$b/vi_bench" "$periods" 20 setup | tail -2 | tr -s ' ' | paste -sd ';')"
done
echo "(cost/loop: best and median of the cost lines over the best loop;" \
  "sum/loop: the best set-up + cost over it (issue 29's target: 1.3);" \
  "$n runs each, Fig. 2, exact, $periods periods)"
