#!/usr/bin/env bash
# Header hygiene: every public header compiles on its own as C99 (pedantic)
# and as C++; the shared libraries export nothing but the vi_ prefix.
set -euo pipefail
src=$1 build=$2 lib=$3
shift 3 # then the I/O libraries (scene, h5)
inc=(-I"$src/include" -I"$build/include")
fail=0
for h in "$src"/include/vibroimpact.h "$src"/include/vibroimpact/*.h; do
  name=${h#"$src/include/"}
  echo "#include <$name>" > "$build/hygiene.c"
  gcc -std=c99 -pedantic -Wall -Wextra -Werror -fsyntax-only "${inc[@]}" "$build/hygiene.c" \
    || { echo "FAIL C99: $name"; fail=1; }
  g++ -std=c++11 -Wall -Wextra -Werror -fsyntax-only "${inc[@]}" -x c++ "$build/hygiene.c" \
    || { echo "FAIL C++: $name"; fail=1; }
done
# C++ linkage: the prototypes are extern "C"
printf '#include <vibroimpact.h>\nint main() { return vi_version_number() == VI_VERSION_NUMBER ? 0 : 1; }\n' \
  > "$build/hygiene.cpp"
g++ -std=c++11 "${inc[@]}" "$build/hygiene.cpp" -o "$build/hygiene_cpp" -L"$(dirname "$lib")" \
  -lvibroimpact -Wl,-rpath,"$(dirname "$lib")" && "$build/hygiene_cpp" || { echo "FAIL: C++ link"; fail=1; }
# VI_DEPRECATED (from vi_export.h) warns the callers of a retired function
printf '#include <vibroimpact.h>\nVI_API VI_DEPRECATED int vi_old(void);\nint f(void);\nint f(void) { return vi_old(); }\n' \
  > "$build/hygiene_dep.c"
for lang in c c++; do
  if gcc -x $lang -Wall -Werror=deprecated-declarations -fsyntax-only "${inc[@]}" \
       "$build/hygiene_dep.c" 2>/dev/null; then
    echo "FAIL: VI_DEPRECATED does not warn ($lang)"; fail=1
  fi
done
for l in "$lib" "$@"; do
  bad=$(nm -D --defined-only "$l" | awk '{print $3}' | grep -Ev '^(vi_|_init$|_fini$)' || true)
  if [ -n "$bad" ]; then echo "FAIL: $l exports: $bad"; fail=1; fi
  echo "$(basename "$l"): $(nm -D --defined-only "$l" | awk '$3 ~ /^vi_/' | wc -l) exported vi_ symbols"
done
[ $fail -eq 0 ] && echo "1 passed, 0 failed"
exit $fail
