#!/usr/bin/env bash
# Builds Locus and runs every unit and integration test. Each phase prints how long it took
# (scripts/phase.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/phase.sh
# Every target, and the API checks' tools (setup.sh times its own install, configure and build).
LOCUS_TARGETS= LOCUS_DEVTOOLS=1 bash scripts/setup.sh
# The API description: lint-clean, and the real server's traffic through Prism's validating
# proxy breaks none of it.
phase "lint openapi" bash scripts/lint_openapi.sh
phase "contract check" bash scripts/contract_check.sh
# The deployment files (docker/): nginx -t and the compose profiles' structure; no docker, no network.
phase "deploy config check" bash scripts/check_deploy_config.sh
root=$(pwd)
cd "${LOCUS_BUILD_DIR:-build}"
# ctest runs more tests at once than there are cores: most integration tests wait on a server
# or a child process, not the CPU (docs/testing.md, "How long the build takes").
jobs="${LOCUS_TEST_JOBS:-$((2 * ${LOCUS_JOBS:-2}))}"
phase "tests (SQLite)" ctest --output-on-failure -j"$jobs" "$@"
# The integration tests (every one starts a real server), again on a throwaway PostgreSQL (the
# replicas and PostgreSQL fault tests run only there); not the script tests whose servers take
# an SQLite file whatever the cluster (label sqlite_only, tests/CMakeLists.txt).
phase "integration tests (PostgreSQL)" "$root/scripts/with_postgres.sh" ctest --output-on-failure -j"$jobs" -L integration -LE sqlite_only "$@"
