#!/usr/bin/env bash
# Hostile input to the commands (issue 29, item 6): each case ends at once
# with a message that names the fault, or says what it costs and stops at
# Ctrl-C; never a hang, a silent exit 0 or a message about something else.
#   hostile_cli_test.sh APP SRC [N [SANITIZED]]   (N: the huge header's
#   dofs, 3e8; SANITIZED: ON for an ASan build)
set -uo pipefail
app=$1
src=$2
big=${3:-300000000}
sanitized=${4:-OFF}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
no() { echo "FAIL: $*"; fail=1; }
# expect STATUS TEXT CMD...: the exit status and a piece of stderr
expect() {
  local want=$1 text=$2
  shift 2
  timeout 20 "$@" > /dev/null 2> "$tmp/err"
  local rc=$?
  [ "$rc" -eq "$want" ] || no "$* : exit $rc, want $want ($(head -c 300 "$tmp/err"))"
  grep -qF -- "$text" "$tmp/err" || no "$* : no '$text' in: $(head -c 300 "$tmp/err")"
}

# a Matrix Market header claiming 3e8 dofs: refused by --max-memory from
# the header alone (it read 2 n zeros first: 6.5 s), by every command
printf '%%%%MatrixMarket matrix coordinate real symmetric\n%d %d 1\n1 1 1.0\n' \
  "$big" "$big" > "$tmp/K.mtx"
cp "$tmp/K.mtx" "$tmp/M.mtx"
printf 'model:\n  matrix_market: {M: M.mtx, K: K.mtx}\n  modes: 2\nforcing: {omega: 0.85}\nstop: {dof: 1, xs: 0.05, r: 0.75}\n' \
  > "$tmp/big.yaml"
for cmd in run truncation energy; do
  expect 2 "more than the 100 MB allowed" timeout 3 "$app" $cmd "$tmp/big.yaml" --max-memory 100M
done
expect 2 "more than the 100 MB allowed" timeout 3 "$app" sweep "$tmp/big.yaml" \
  --param forcing.omega --from 0.8 --to 0.9 --steps 2 --max-memory 100M
# ... before anything of n is allocated: under an address-space limit of
# 1 GB, far below the scene's 7 vectors of n doubles (16.8 GB for 3e8 dofs;
# a calloc of them failed there, "out of memory", exit 1), every door says
# the budget, with the vectors' own 56 n bytes.  Not under ASan, whose
# shadow memory needs terabytes of address space.
if [ "$sanitized" != ON ] && [ "$big" -ge 30000000 ]; then
  mb=$(awk -v n="$big" 'BEGIN { printf "%.3g", 56 * n / 1048576 }')
  for args in "run $tmp/big.yaml" "truncation $tmp/big.yaml" "energy $tmp/big.yaml" \
    "run $tmp/big.yaml --set forcing.omega=0.9" \
    "sweep $tmp/big.yaml --param forcing.omega --from 0.8 --to 0.9 --steps 2"; do
    # shellcheck disable=SC2086 # the arguments are words
    expect 2 "vectors of $big dofs alone would need $mb MB (the model more), more than the 100 MB allowed" \
      bash -c 'ulimit -v 1000000 && exec timeout 3 "$@"' sh "$app" $args --max-memory 100M
  done
  # ... and without --max-memory: the budget is what the address-space
  # limit leaves, not the machine's free memory (the calloc failed: "out of
  # memory", exit 1)
  for args in "run $tmp/big.yaml" \
    "sweep $tmp/big.yaml --param forcing.omega --from 0.8 --to 0.9 --steps 2"; do
    # shellcheck disable=SC2086 # the arguments are words
    expect 2 "vectors of $big dofs alone would need $mb MB (the model more), more than the" \
      bash -c 'ulimit -v 1000000 && exec timeout 3 "$@"' sh "$app" $args
    grep -Eq "more than the (9[0-9]{2}|[0-9]{1,2}[0-9]?) MB available to this process" "$tmp/err" ||
      no "ulimit -v 1000000, $args: the budget is not the limit's: $(head -c 300 "$tmp/err")"
  done
fi

# one parameter on both axes of a map (one axis was ignored), also spelt
# two ways
expect 2 "both name forcing.omega" "$app" basins --param forcing.omega --from 0.8 \
  --to 0.9 --steps 2 --param2 forcing.omega --from2 0.8 --to2 0.9 --steps2 2
expect 2 "both name stops[1].xs" "$app" basins --param stop.xs --from 0.1 --to 0.2 \
  --steps 2 --param2 'stops[1].xs' --from2 0.1 --to2 0.2 --steps2 2

# a bad number named with the command the user typed (basins said "sweep:")
expect 2 "basins: --steps: 'abc' is not a finite number" "$app" basins --param \
  forcing.omega --from 0.8 --to 0.9 --steps abc --param2 stop.r --from2 0.5 --to2 0.9 --steps2 2
expect 2 "basins: --max-memory" "$app" basins --max-memory 0 --param forcing.omega \
  --from 0.8 --to 0.9 --steps 2 --param2 stop.r --from2 0.5 --to2 0.9 --steps2 2
expect 2 "sweep: --steps must be an integer" "$app" sweep --param forcing.omega \
  --from 0.8 --to 0.9 --steps 0

# a library parameter the scene does not spell: named, with the scene's keys
expect 2 "damping.scale is a parameter of the model (vi_param.h), not a key of the scene" \
  "$app" sweep --param damping.scale --from 0.8 --to 0.9 --steps 2
expect 2 "model.chain.m, .k, .c" "$app" sweep --param forcing.omega --from 0.8 --to 0.9 \
  --steps 2 --param2 damping.scale --from2 1 --to2 2 --steps2 2

# --help to a full device is a lost output, as for the other commands
for cmd in sweep basins run curves; do
  "$app" $cmd --help > /dev/full 2> "$tmp/err"
  [ $? -eq 1 ] || no "$cmd --help > /dev/full: exit status"
  grep -q "cannot write the standard output" "$tmp/err" || no "$cmd --help > /dev/full: message"
done

# every command's --help is the help alone (curves printed an empty
# result after it: "? curve of ... ((null), (null))")
for cmd in run sweep basins orbits curves truncation energy identify; do
  "$app" $cmd --help > "$tmp/help" 2> "$tmp/err" || no "$cmd --help: exit status"
  if grep -q "(null)" "$tmp/help" "$tmp/err"; then no "$cmd --help prints (null)"; fi
done

# a count beyond the limit says the limit
expect 2 "in [1, 100000000] (got '1000000000')" "$app" sweep --param forcing.omega \
  --from 0.8 --to 0.9 --steps 1000000000

# a curve's search that ends where it begins (the default scene's Omega
# is 0.9): refused at once; its step of no length spun forever
expect 2 "forcing.omega: the search's end 0.90000000000000002 is the model's value" \
  "$app" curves --kind pd --param forcing.omega --to 0.9 --param2 stop.r --from2 0.5 --to2 0.9
expect 2 "nothing to search" "$app" curves --kind grazing --orbit 1,0 --param stop.xs \
  --to 0.1 --param2 forcing.omega --from2 0.5 --to2 1.8

# a study's key the model does not have, or cannot vary: named, with why
# (orbits said "out of memory" for forcing.a[3] of Fig. 2's two
# coordinates, curves "invalid argument")
expect 2 "forcing.a[3]: index 3 is outside 1..2 (coordinates)" \
  "$app" orbits --continue 'forcing.a[3]' --to 1
expect 2 "initial.x[1] is the initial state" "$app" orbits --continue 'initial.x[1]' --to 1
expect 2 "--param2: stops[2].r: index 2 is outside 1..1 (stops)" "$app" curves --kind pd \
  --param forcing.omega --to 1.8 --param2 'stops[2].r' --from2 0.5 --to2 0.9
expect 2 "--param2 initial.x[1] is an initial-state key" "$app" curves --kind pd \
  --param forcing.omega --to 1.8 --param2 'initial.x[1]' --from2 0.5 --to2 0.9
expect 2 "--param forcing.omega and --param2 forcing.omega name one parameter" "$app" curves \
  --kind pd --param forcing.omega --to 1.8 --param2 forcing.omega --from2 0.5 --to2 0.9
expect 2 "--param stop.r and --param2 stops[1].r name one parameter" "$app" curves \
  --kind pd --param stop.r --to 0.5 --param2 'stops[1].r' --from2 0.5 --to2 0.9
expect 2 "--steps must be a whole number in [1, 1000000] (got '100000000')" "$app" curves \
  --kind pd --param forcing.omega --to 1.8 --param2 stop.r --from2 0.5 --to2 0.9 \
  --steps 100000000

# a fitted key twice (fitted at two values, each "not determined", exit 0)
expect 2 "--fit: stop.r is listed twice" "$app" identify "$src/share/scenes/fig2.yaml" \
  --data "$src/tests/study/data/fig2.csv" --fit stop.r,stop.r
expect 2 "parameter 2: stop.r is parameter 1 already" "$app" identify \
  "$src/share/scenes/fig2.yaml" --data "$src/tests/study/data/fig2.csv" --fit 'stop.r,stops[1].r'

# a recording in milliseconds against a model in seconds: the forcing
# frequency would be 1000 times the start (it went on to fit 900 rad/s)
awk -F, '/^#/ || /^t/ {next} {for (k = 0; k < 4; k++) a[k] = a[k] sprintf("%.17g,%s\n",
     ($1 + k * 6.981317007977318) * 1000, $2)} END {printf "t,x\n"; for (k = 0; k < 4; k++)
     printf "%s", a[k]}' "$src/tests/study/data/fig2.csv" > "$tmp/ms.csv"
expect 2 "is the recording's time in the model's unit?" "$app" identify \
  "$src/share/scenes/fig2.yaml" --data "$tmp/ms.csv" --fit forcing.omega,stop.r

# a mass so small that omega^2 overflows (NaN frequencies, exit 0 once):
# a scene's number that underflows is named so, the model key refused
expect 2 "under- or overflows" "$app" run "$src/share/scenes/chain5.yaml" \
  --set model.chain.m=1e-308
expect 2 "under- or overflows" "$app" sweep --param mass.scale --from 1e-308 \
  --to 1 --steps 2

# a key no study changes is named as such, not what its value breaks
expect 2 "model.chain.n: not a parameter a study can change" "$app" sweep \
  "$src/share/scenes/chain5.yaml" --param model.chain.n --from 2 --to 4 --steps 3

# a reference of 198 modes (minutes of orbit search): said before the
# search, and Ctrl-C ends it (exit 130)
"$app" truncation "$src/share/scenes/beam_fe.yaml" --modes 1..3 --reference 198 \
  > /dev/null 2> "$tmp/trunc" &
pid=$!
for _ in $(seq 200); do
  grep -q "may take minutes" "$tmp/trunc" && break
  sleep 0.1
done
grep -q "reference's 198 modes reach omega = 1.4" "$tmp/trunc" ||
  no "truncation --reference 198: no word of its cost: $(cat "$tmp/trunc")"
kill -INT $pid
for _ in $(seq 50); do kill -0 $pid 2> /dev/null || break; sleep 0.1; done
if kill -0 $pid 2> /dev/null; then
  no "truncation: Ctrl-C did not end it within 5 s"
  kill -KILL $pid
fi
wait $pid
[ $? -eq 130 ] || no "truncation after SIGINT: exit status, want 130"

[ $fail -eq 0 ] && echo "hostile command-line input: all cases answered"
exit $fail
