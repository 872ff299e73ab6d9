#!/usr/bin/env bash
# Builds Locus and runs every unit and integration test.
set -euo pipefail
cd "$(dirname "$0")/.."
LOCUS_TARGETS= LOCUS_DEVTOOLS=1 bash scripts/setup.sh   # every target, and the API checks' tools
# The API description: lint-clean, and the real server's traffic through Prism's validating
# proxy breaks none of it.
bash scripts/lint_openapi.sh
bash scripts/contract_check.sh
# The deployment files (docker/): nginx -t and the compose profiles' structure; no docker, no network.
bash scripts/check_deploy_config.sh
root=$(pwd)
cd "${LOCUS_BUILD_DIR:-build}"
ctest --output-on-failure -j"${LOCUS_JOBS:-2}" "$@"
# The integration tests (every one starts a real server), again on a throwaway PostgreSQL (the
# replicas and PostgreSQL fault tests run only there).
"$root/scripts/with_postgres.sh" ctest --output-on-failure -j"${LOCUS_JOBS:-2}" -L integration "$@"
