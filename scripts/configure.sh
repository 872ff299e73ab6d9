#!/usr/bin/env bash
# Configures a build folder: scripts/configure.sh DIR [CMAKE_ARG…] runs cmake -S . -B DIR with
# the arguments, using Ninja when it is installed and DIR is new (a folder keeps the generator it
# was made with). Ninja compiles a program's own sources while the libraries it links are still
# building, where Make waits for them: both cores stay busy to the end of the build
# (docs/testing.md, "How long the build takes"). setup.sh, test_sanitized.sh and fuzz.sh use it.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -eq 0 ]; then
  echo "usage: scripts/configure.sh BUILD_DIR [CMAKE_ARG…]" >&2
  exit 2
fi
dir=$1
shift
generator=()
if [ ! -f "$dir/CMakeCache.txt" ] && command -v ninja >/dev/null 2>&1; then
  generator=(-G Ninja)
fi
exec cmake -S . -B "$dir" "${generator[@]}" "$@"
