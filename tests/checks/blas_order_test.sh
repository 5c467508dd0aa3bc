#!/usr/bin/env bash
# blas_order_test.sh PROGRAM... : each program loads BLAS before GSL's
# reference CBLAS.  A program's symbols bind in its load order, so with
# libgslcblas first, libvibroimpact's cblas_dgemm would run GSL's reference
# loops (the modal set-up of a 1000-mass chain 5x slower).
set -euo pipefail
status=0
for prog in "$@"; do
  order=$(ldd "$prog" | awk '/libgslcblas|libblas\.so|libopenblas/ {print $1}')
  first=$(printf '%s\n' "$order" | head -n 1)
  case "$first" in
    libgslcblas*) echo "FAIL: $prog loads libgslcblas before BLAS:" $order; status=1 ;;
    "") echo "note: $prog loads no CBLAS" ;;
    *) echo "ok: $prog binds CBLAS to $first" ;;
  esac
done
exit $status
