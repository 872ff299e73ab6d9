#!/usr/bin/env bash
# Builds the server and the CLI (not the tests and benchmarks: scripts/test.sh builds those)
# and starts the server on http://127.0.0.1:8080 with an SQLite file (locus.db) that gets a
# small demo map the first time. Override with LOCUS_DB, LOCUS_PORT, LOCUS_HOST.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh locus-server locus
exec "${LOCUS_BUILD_DIR:-build}/bin/locus-server" --db "${LOCUS_DB:-locus.db}" \
  --host "${LOCUS_HOST:-127.0.0.1}" --port "${LOCUS_PORT:-8080}" --demo "$@"
