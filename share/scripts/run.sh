#!/usr/bin/env bash
# Build (Release) and run the app; with no arguments, the default Fig. 2 scene.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
"$root/share/scripts/deps.sh"
"$root/share/scripts/configure.sh" "$root/build/release" "$root" -DCMAKE_BUILD_TYPE=Release \
      -DVI_BUILD_TESTS=OFF >/dev/null
cmake --build "$root/build/release" -j"$(nproc)" >/dev/null
exec "$root/build/release/vibroimpact" "$@"
