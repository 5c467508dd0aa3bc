#!/usr/bin/env bash
# The README's C example compiles as given (-std=c11, warnings as errors)
# and does what the README says: it runs the paper's Fig. 2 scene for 100
# forcing periods and prints every impact.
#   test_readme_example.sh SRC BUILD LIB [CC]
#
# What it must print, from the physics: the run settles on the P(1,1) orbit
# (one impact per forcing period), so 100 periods give about 100 impacts
# (the first comes at t = 1.56, inside the first period; a transient may
# add or drop a few: 95..105 accepted).  Once settled, consecutive impacts
# are one period 2 pi / 0.9 = 6.9813170 apart and the approach velocity is
# the orbit's v_N = 0.787661, found independently by Newton shooting on the
# closed-form flow (vi_orbit, `vibroimpact energy`; README section on the
# energy balance): tolerance 1e-4 on v_N and 1e-6 on the period, far above
# the run's rtol 1e-10 yet far below the 0.05 spread of the transient.
set -euo pipefail
src=$1 build=$2 lib=$3 cc=${4:-cc}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
awk '/^## The library in C/ {f = 1; next}
     f && /^```c/ {g = 1; next}
     g && /^```/ {exit}
     g' "$src/README.md" > "$tmp/example.c"
if [ ! -s "$tmp/example.c" ]; then
  echo "FAIL: no \`\`\`c block under '## The library in C' in README.md"; exit 1
fi
libdir=$(dirname "$lib")
"$cc" -std=c11 -Wall -Wextra -Werror -I"$src/include" -I"$build/include" \
  "$tmp/example.c" -o "$tmp/example" -L"$libdir" -lvibroimpact -Wl,-rpath,"$libdir" \
  || { echo "FAIL: the README's C example does not compile with -std=c11 -Wall -Wextra -Werror"; exit 1; }
"$tmp/example" > "$tmp/out" || { echo "FAIL: the example exited $?"; exit 1; }
awk '
  /t = / { n++; tprev = t; t = $3; vn = $6 }
  END {
    period = 2 * 3.14159265358979323846 / 0.9
    printf "%d impacts; last: t = %.10f, v_n = %.10f, spacing %.10f (period %.10f)\n",
           n, t, vn, t - tprev, period
    bad = 0
    if (n < 95 || n > 105) { print "FAIL: impact count outside 95..105"; bad = 1 }
    if (vn - 0.787661 > 1e-4 || 0.787661 - vn > 1e-4) {
      print "FAIL: last v_n is not the P(1,1) value 0.787661 (1e-4)"; bad = 1 }
    d = t - tprev - period
    if (d > 1e-6 || -d > 1e-6) { print "FAIL: last impacts not one period apart (1e-6)"; bad = 1 }
    if (!bad) print "1 passed, 0 failed"
    exit bad
  }' "$tmp/out"
