#!/usr/bin/env bash
# The contributor's quick check after a change: rebuilds one test executable (and what it
# links, and for the integration groups locus-server and locus) in build/, then runs all of its
# tests in one process. Only what changed is recompiled (ccache serves the rest after a branch
# switch). The groups are in tests/CMakeLists.txt, e.g. unit_fusion for client-lib/motion/fusion,
# unit_plan for shared/src/plan, integration_store_tracks for server/tracks.
#   scripts/quick_check.sh unit_plan                              # every test of the group
#   scripts/quick_check.sh unit_plan --gtest_filter='PlanRoute.*'  # gtest's own flags pass through
# Needs a configured build/ (scripts/run.sh or scripts/test.sh made it). The whole suite on both
# backends is still scripts/test.sh's job.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -eq 0 ] || [[ "$1" == -* ]]; then
  echo "usage: scripts/quick_check.sh TEST_EXECUTABLE [GTEST_FLAG…]   (groups: tests/CMakeLists.txt)" >&2
  exit 2
fi
target=$1
shift
BUILD_DIR="${LOCUS_BUILD_DIR:-build}"
[ -f "$BUILD_DIR/CMakeCache.txt" ] || { echo "quick_check: no $BUILD_DIR/ yet: run scripts/run.sh or scripts/test.sh once" >&2; exit 2; }
source scripts/phase.sh
phase "build $target" cmake --build "$BUILD_DIR" -j"${LOCUS_JOBS:-2}" --target "$target"
phase "run $target" "$BUILD_DIR/bin/$target" --gtest_brief=1 "$@"
