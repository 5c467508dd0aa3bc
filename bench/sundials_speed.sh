#!/usr/bin/env bash
# Adams, BDF and ERK on Debian's binary SUNDIALS against the -O3 build of the
# same sources (share/scripts/build-sundials.sh): the same vi_wp binary, the
# library swapped with LD_LIBRARY_PATH (searched before the rpath), runs
# interleaved: the best of 5 loops in each process, the median over 7
# processes (on a shared machine a single lucky or unlucky process is noise).
# Prints wall times, their ratio, and whether steps and impacts are
# identical.  Usage: bench/sundials_speed.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build/release}
wp=$build/vi_wp
gcc -O2 -std=c99 -D_GNU_SOURCE "$root/bench/vi_wp.c" -I"$root/include" \
  -I"$build/include" -L"$build" -lvibroimpact_h5 -lvibroimpact_scene -lvibroimpact \
  -Wl,-rpath,"$build" -o "$wp"
debian=/usr/lib/$(gcc -print-multiarch)
echo "optimised: $(ldd "$wp" | awk '/sundials_cvodes/{print $3}')"
echo "Debian:    $(LD_LIBRARY_PATH=$debian ldd "$wp" | awk '/sundials_cvodes/{print $3}')"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '%-10s %-6s %-6s %12s %12s %7s %s\n' scene method rtol "Debian ms" "-O3 ms" ratio "same steps and impacts"
for sc in fig2:share/scenes/fig2.yaml:0.9:100 chain20:bench/scenes/chain20.yaml:0.15:20; do
  IFS=: read -r name file om per <<<"$sc"
  t_end=$(awk -v o="$om" -v p="$per" 'BEGIN{printf "%.17g", p*2*3.141592653589793/o}')
  for m in adams bdf erk; do
    for rtol in 1e-8 1e-10; do
      atol=$(awk -v r="$rtol" 'BEGIN{print r/100}')
      : >"$tmp/td"
      : >"$tmp/to"
      for rep in 1 2 3 4 5 6 7; do
        LD_LIBRARY_PATH=$debian "$wp" "$root/$file" $m $rtol $atol "$t_end" 5 "$tmp/d"
        "$wp" "$root/$file" $m $rtol $atol "$t_end" 5 "$tmp/o"
        awk '/^# wall/{print $3*1e3}' "$tmp/d" >>"$tmp/td"
        awk '/^# wall/{print $3*1e3}' "$tmp/o" >>"$tmp/to"
      done
      bd=$(sort -g "$tmp/td" | sed -n 4p)
      bo=$(sort -g "$tmp/to" | sed -n 4p)
      same=no
      # the same steps and the same impacts to the last digit
      if [ "$(sed 1d "$tmp/d" | md5sum)" = "$(sed 1d "$tmp/o" | md5sum)" ] &&
         [ "$(head -1 "$tmp/d" | grep -o 'steps [0-9]*')" = "$(head -1 "$tmp/o" | grep -o 'steps [0-9]*')" ]; then
        same=yes
      fi
      printf '%-10s %-6s %-6s %12.2f %12.2f %7.2f %s (%s)\n' "$name" $m $rtol "$bd" "$bo" \
        "$(awk -v a="$bd" -v b="$bo" 'BEGIN{print a/b}')" $same \
        "$(head -1 "$tmp/o" | grep -o 'steps [0-9]*')"
    done
  done
done
