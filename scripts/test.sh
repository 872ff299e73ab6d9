#!/usr/bin/env bash
# Builds Locus and runs every unit and integration test.
set -euo pipefail
cd "$(dirname "$0")/.."
LOCUS_TARGETS= bash scripts/setup.sh   # every target: the tests and benchmarks too
cd "${LOCUS_BUILD_DIR:-build}"
ctest --output-on-failure -j"${LOCUS_JOBS:-2}" "$@"
