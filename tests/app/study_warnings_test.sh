#!/usr/bin/env bash
# A study's failed values are summarised, not listed (issue 29: a 40 x 40
# basins map half beyond the stop printed 680 lines under --quiet).
#   study_warnings_test.sh APP
# Fig. 2's stop is at x_s = 0.1: of initial.x[2] = -0.5 + 1.2 i / 9
# (i = 0..9) the five values above 0.1 start beyond it, so 50 of the
# 10 x 10 cells fail, whatever initial.v[2] is.
set -uo pipefail
app=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
no() { echo "FAIL: $*"; fail=1; }
map=(basins --param 'initial.x[2]' --from -0.5 --to 0.7 --steps 10
     --param2 'initial.v[2]' --from2 -1 --to2 1 --steps2 10
     --transient 10 --record 5 --threads 1)

"$app" "${map[@]}" --quiet > "$tmp/out" 2> "$tmp/err"
[ $? -eq 0 ] || no "basins --quiet exit status"
[ "$(wc -l < "$tmp/err")" -eq 1 ] || no "basins --quiet: $(wc -l < "$tmp/err") lines of warnings, want 1"
grep -q '50 of 100 cells failed' "$tmp/err" || no "basins: no count of 50 of 100 cells"
grep -q 'the first: initial.x\[2\] = 0.1666.*, initial.v\[2\] = -1: .*violates the stop' "$tmp/err" ||
  no "basins: the first failed cell, with both of its values"
grep -q -- '--json lists every message' "$tmp/err" || no "basins: where the list is"
grep -q 'next value' "$tmp/err" && no "basins: a cell does not warm-start the next"

"$app" "${map[@]}" --json -o "$tmp/b.h5" > "$tmp/json" 2> "$tmp/err"
grep -q "the JSON's \"failed\"" "$tmp/err" || no "basins --json: where the list is"
/usr/bin/python3 - "$tmp/json" <<'PY' || fail=1
import json, sys
d = json.load(open(sys.argv[1]))
bad = d["failed"]
ok = len(bad) == 50 and all(c["param"] > 0.1 and "initial.v[2] = " in c["error"]
                             for c in bad)
ok = ok and sum(1 for n in d["n"] if n is None) >= 50
if not ok:
    print("FAIL: basins --json: the failed list", bad[:2])
    sys.exit(1)
PY
# cells are independent: the map is the same however its lines are cut
# (default: pieces of about 8 cells) and on however many threads, failed
# cells included
for split in "--chunks 10" "--chunks 1" "--chunks 3 --threads 2"; do
  "$app" "${map[@]}" $split --json > "$tmp/json_s" 2> /dev/null
  /usr/bin/python3 - "$tmp/json" "$tmp/json_s" "$split" <<'PY' || fail=1
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
for d in (a, b):
    for k in ("chunks", "split", "wall", "threads"):
        d.pop(k, None)
if a != b:
    print("FAIL: basins %s differs from the default split in %s" %
          (sys.argv[3], [k for k in a if a[k] != b.get(k)]))
    sys.exit(1)
PY
done
"$app" "${map[@]}" -o "$tmp/c.h5" > /dev/null 2> "$tmp/err"
grep -q "each marked n = -1 in $tmp/c.h5" "$tmp/err" || no "basins -o: where the cells are marked"

# a sweep with one failed value: one line, and what follows it
"$app" sweep --param 'initial.x[2]' --from 0 --to 0.2 --steps 3 --transient 10 \
  --record 5 --quiet > /dev/null 2> "$tmp/err"
[ "$(wc -l < "$tmp/err")" -eq 1 ] || no "sweep: one failed value, one line"
grep -q 'initial.x\[2\] = 0.2.*(marked failed; the next value starts from the scene' "$tmp/err" ||
  no "sweep: the warning of its one failed value"
# and with three: one line, the count
"$app" sweep --param 'initial.x[2]' --from -0.05 --to 0.35 --steps 5 --transient 10 \
  --record 5 --quiet > /dev/null 2> "$tmp/err"
[ "$(wc -l < "$tmp/err")" -eq 1 ] || no "sweep: three failed values, one line"
grep -q '3 of 5 values failed and are marked so; the value after each starts' "$tmp/err" ||
  no "sweep: the count of its failed values"
[ $fail -eq 0 ] && echo "ok: study warnings summarised"
exit $fail
