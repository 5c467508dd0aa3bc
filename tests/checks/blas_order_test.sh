#!/usr/bin/env bash
# blas_order_test.sh PROGRAM... : each program loads BLAS before GSL's
# reference CBLAS.  A program's symbols bind in its load order, so with
# libgslcblas first, libvibroimpact's cblas_dgemm would run GSL's reference
# loops (the modal set-up of a 1000-mass chain 5x slower).
set -u
status=0
for prog in "$@"; do
  # ldd once more if it fails (seen once under a loaded parallel ctest):
  # the load order, not ldd, is what is checked
  if ! out=$(ldd "$prog" 2>&1) && ! out=$(ldd "$prog" 2>&1); then
    echo "FAIL: ldd $prog: $out"
    status=1
    continue
  fi
  order=$(awk '/libgslcblas|libblas\.so|libopenblas/ {print $1}' <<< "$out")
  first=${order%%$'\n'*}
  case "$first" in
    libgslcblas*) echo "FAIL: $prog loads libgslcblas before BLAS:" $order; status=1 ;;
    "") echo "FAIL: $prog loads no CBLAS at all"; status=1 ;;
    *) echo "ok: $prog binds CBLAS to $first" ;;
  esac
done
exit $status
