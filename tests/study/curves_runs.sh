#!/usr/bin/env bash
# The program's runs of curves_check.py, codim2_check.py and cusp_check.py,
# without their mpmath references: the sanitized build's test of
# `vibroimpact curves`.  Those checks compare each curve with a closed form
# computed in Python to 24 or 60 digits (most of their CPU-seconds, which
# no sanitizer sees); they run in the Release build, and the sanitized build
# runs here the same invocations, the same C paths: each must exit 0 with
# a JSON whose curve has points (and the orbits' branches a period
# doubling).  Keep the list in step with the three scripts' run() calls.
#   curves_runs.sh APP
set -u
app=$1
py=/usr/bin/python3
fail=0
# json CHECK ARGS...: the program's JSON on ARGS, CHECK a Python expression on j
json() {
  local check=$1 out rc
  shift
  out=$("$app" "$@")
  rc=$?
  if [ $rc -ne 0 ]; then
    echo "FAIL: exit $rc: $*"
    fail=1
    return
  fi
  $py -c "import json, sys; j = json.load(sys.stdin); assert $check, sys.argv[1:]" "$*" \
    <<< "$out" || { echo "FAIL: $check: $*"; fail=1; }
  echo "ok   $*"
}
pts='len(j["points"]) > 10'
pd='any(e["type"] == "period_doubling" for b in j["branches"] for e in b["events"])'
# curves_check.py, checks 1 to 8, 10 and 11 (9 runs with --fold only)
json "$pd" orbits --continue forcing.omega --to 1.8 --json
json "$pd" orbits --continue forcing.omega --to 1.8 --json --arclength
json "$pts" curves --kind pd --param forcing.omega --to 1.8 --param2 stop.r --from2 0.5 \
  --to2 0.9 --json
# (the two 2-D sweeps at a few cells and a short transient: their C paths,
# not their resolution, which curves_check.py needs to bound the curves)
json 'len(j["lines"]) == 3' sweep --param forcing.omega --from 1.56 --to 1.68 --steps 5 \
  --param2 stop.r --from2 0.5 --to2 0.9 --steps2 3 --transient 100 --record 40 --threads 2 \
  --json --quiet
json "$pts" curves --kind grazing --orbit 1,0 --param stop.xs --to 5 --param2 forcing.omega \
  --from2 0.5 --to2 1.8 --json
json "$pts" curves --set stop.xs=0.5 --kind fold --param forcing.omega --to 2.5 --param2 stop.xs \
  --from2 0 --to2 1.5 --steps 100 --json
json "$pts" curves --set stop.r=0.6 --set stop.xs=0.2 --set model.chain.c=0.02 --kind ns \
  --param forcing.omega --to 3 --param2 stop.r --from2 0.3 --to2 0.9 --json
json "$pts" curves --set forcing.omega=1.65 --orbit 2,2 --kind pd --param forcing.omega --to 1.8 \
  --param2 stop.r --from2 0.5 --to2 0.9 --json
json 'len(j["lines"]) == 3' sweep --param forcing.omega --from 1.64 --to 1.72 --steps 5 \
  --param2 stop.r --from2 0.5 --to2 0.9 --steps2 3 --transient 100 --record 40 --threads 2 \
  --json --quiet
json "$pts" curves --set model.chain.c=0.02 --set stop.r=0.8 --set forcing.omega=0.44 \
  --set stop.xs=1.05 --orbit 2,2 --kind ns --param forcing.omega --to 0.38 --param2 stop.xs \
  --from2 0.9 --to2 1.3 --json
json "$pts" curves --set forcing.omega=1.65 --orbit 2,2 --kind grazing --param forcing.omega \
  --to 1.8 --param2 stop.r --from2 0.6 --to2 0.8 --steps 50 --json
# codim2_check.py: the special points its four curves report
base=(--set model.chain.c=0.02 --set stop.r=0.8 --set forcing.omega=0.5)
json 'sum(e["type"] == "resonance_1_2" for e in j["special"]) == 2' curves "${base[@]}" \
  --set stop.xs=1.233 --kind pd --param forcing.omega --to 0.3 --param2 stop.xs --from2 1.1 \
  --to2 1.4 --json
json "$pts" curves "${base[@]}" --set stop.xs=1.15 --kind ns --param forcing.omega --to 0.56 \
  --param2 stop.xs --from2 1.0 --to2 1.4 --json
json 'any(e["type"] == "resonance_1_1" for e in j["special"])' curves --set stop.r=0.6 \
  --set stop.xs=0.2 --set model.chain.c=0.02 --kind ns --param forcing.omega --to 3 \
  --param2 stop.xs --from2 0 --to2 2 --json
json 'any(e["type"] == "resonance_1_1" for e in j["special"])' curves --set stop.xs=0.5 \
  --kind fold --param forcing.omega --to 2.5 --param2 stop.xs --from2 0 --to2 1.5 --steps 100 \
  --json
# cusp_check.py: the P(2,2) fold curve through its located cusp
json 'sum(e["type"] == "cusp" and e["located"] for e in j["special"]) == 1' curves \
  --set model.chain.c=0.05 --set forcing.omega=0.535 --set stop.xs=1.285 --orbit 2,2 --kind fold \
  --param forcing.omega --to 0.52 --param2 stop.xs --from2 1.27 --to2 1.31 --json
exit $fail
