#!/usr/bin/env bash
# The finite-element scenes shipped in share/scenes (impacting_bar.yaml,
# beam_fe.yaml and their Matrix Market files) are what share/fe/fe_models.py
# writes, byte for byte: they cannot drift from the script that documents
# where each number comes from.
#   fe_files_test.sh SRC
set -euo pipefail
src=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 "$src/share/fe/fe_models.py" bar "$tmp"
/usr/bin/python3 "$src/share/fe/fe_models.py" beam "$tmp"
fail=0
for f in "$tmp"/*; do
  b=$(basename "$f")
  if ! cmp -s "$f" "$src/share/scenes/$b"; then
    echo "FAIL: share/scenes/$b differs from what share/fe/fe_models.py writes"
    fail=1
  fi
done
echo "$(ls "$tmp" | wc -l) files compared"
exit $fail
