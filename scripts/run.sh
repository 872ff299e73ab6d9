#!/usr/bin/env bash
# Builds the server only (the CLI, tests and benchmarks: `scripts/setup.sh locus` or
# scripts/test.sh; the server alone serves in a third of the time) and starts it on http://127.0.0.1:8080 with an SQLite file (locus.db) that gets a
# small demo map the first time. Override with LOCUS_DB, LOCUS_PORT, LOCUS_HOST, or with the
# server's own flags (`./scripts/run.sh --port 9090`), which win over those. LOCUS_NO_BUILD=1
# starts the binaries already built in LOCUS_BUILD_DIR (default build/) without the set-up.
set -euo pipefail
cd "$(dirname "$0")/.."
[ "${LOCUS_NO_BUILD:-0}" = 1 ] || bash scripts/setup.sh locus-server
defaults=()
given() {  # is flag $1 among the arguments, as `--flag V` or `--flag=V`?
  local flag=$1 arg
  shift
  for arg in "$@"; do [[ "$arg" == "$flag" || "$arg" == "$flag="* ]] && return 0; done
  return 1
}
given --db "$@" || defaults+=(--db "${LOCUS_DB:-locus.db}")
given --host "$@" || defaults+=(--host "${LOCUS_HOST:-127.0.0.1}")
given --port "$@" || defaults+=(--port "${LOCUS_PORT:-8080}")
exec "${LOCUS_BUILD_DIR:-build}/bin/locus-server" "${defaults[@]}" --demo "$@"
