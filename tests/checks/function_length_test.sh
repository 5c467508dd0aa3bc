#!/usr/bin/env bash
# The program stays a thin layer (issue 19): no function in apps/ is longer
# than the limit (default 100 lines, from the line of its name to its
# closing brace).  House style puts a definition's name at column 0 and
# its braces alone at column 0, which is what this reads; a brace left at
# column 0 inside a string or comment would cut a function short, so the
# check errs on the side of passing.  Lists every function over the limit.
#   function_length_test.sh SRC [LIMIT]
set -uo pipefail
src=$1 limit=${2:-100}
shopt -s nullglob
files=("$src"/apps/*.c)
[ ${#files[@]} -gt 0 ] || { echo "FAIL: no C files in $src/apps"; exit 1; }
awk -v limit="$limit" -v root="$src/" '
  FNR == 1 { name = ""; start = 0; body = 0 }
  # a definition starts at column 0 with its name (not a comment, a
  # preprocessor line, a declaration ending in ";" or an initializer)
  !body && /^[A-Za-z_][A-Za-z0-9_ \t\*]*\(/ && !/;[ \t]*$/ && !/=/ {
    line = $0
    sub(/\(.*/, "", line)
    n = split(line, w, /[ \t\*]+/)
    name = w[n]; start = FNR
  }
  !body && /^\{/ && name != "" { body = 1; next }
  body && /^\}/ {
    len = FNR - start + 1
    count++
    if (len > limit) {
      f = FILENAME; sub(root, "", f)
      printf "FAIL %s: %s is %d lines (limit %d)\n", f, name, len, limit
      bad++
    }
    if (len > longest) { longest = len; lname = name }
    body = 0; name = ""
  }
  END {
    printf "%d functions in apps/, the longest %s (%d lines), %d over %d\n",
           count, lname, longest, bad, limit
    exit bad > 0
  }' "${files[@]}"
