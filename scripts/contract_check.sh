#!/usr/bin/env bash
# Contract check: the real locus-server against schema/openapi.yaml.
#
# Starts build/bin/locus-server (LOCUS_BUILD_DIR to use another build directory) on a free
# 127.0.0.1 port with a temporary database, an API key and a 64 KiB body limit, puts Prism's
# validating proxy in front of it, and sends every operation of the spec through the proxy:
# valid requests and the main bad inputs (scripts/contract_check.mjs has the list). Fails,
# listing each violation, when Prism finds a request or an answer off the spec, when the spec
# accepts a request the server refuses, or when an operation goes unexercised. Prints
# "contract: N requests, V violations (...)". Needs `npm ci` at the repository root first.
#
# CONTRACT_SKIP=opId,opId leaves operations out (they are named in the summary), for a
# server that does not serve them yet.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${LOCUS_BUILD_DIR:-build}
case "$BUILD_DIR" in /*) ;; *) BUILD_DIR=$ROOT/$BUILD_DIR ;; esac
SERVER=$BUILD_DIR/bin/locus-server
PRISM=$ROOT/node_modules/.bin/prism
REDOCLY=$ROOT/node_modules/.bin/redocly
SPEC=$ROOT/schema/openapi.yaml
STARTUP_SECONDS=${CONTRACT_STARTUP_SECONDS:-60}   # Prism takes a few seconds on a busy machine
RUN_SECONDS=${CONTRACT_RUN_SECONDS:-300}

# No usage data to Redocly, no look-up of newer versions.
export REDOCLY_TELEMETRY=off REDOCLY_SUPPRESS_UPDATE_NOTICE=true

die() { echo "contract: $*" >&2; exit 2; }
[ -x "$SERVER" ] || die "no $SERVER: build the locus-server target first (or set LOCUS_BUILD_DIR)"
[ -x "$PRISM" ] && [ -x "$REDOCLY" ] || die "no Prism/Redocly under node_modules: run 'npm ci' in $ROOT"
command -v node >/dev/null || die "node is not installed"

TMP=$(mktemp -d "${TMPDIR:-/tmp}/locus-contract.XXXXXX")
SERVER_PID=""
PRISM_PID=""
cleanup() {
    local pid
    for pid in $PRISM_PID $SERVER_PID; do
        kill "$pid" 2>/dev/null || true
    done
    for pid in $PRISM_PID $SERVER_PID; do
        # Up to 5 s for a clean stop, then force it.
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2>/dev/null || true
    done
    rm -rf "$TMP"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# Waits until FILE holds a line matching REGEX (or the process PID has died, or time is up).
wait_for() {
    local file=$1 regex=$2 pid=$3 what=$4 deadline=$((SECONDS + STARTUP_SECONDS))
    until grep -Eq "$regex" "$file" 2>/dev/null; do
        kill -0 "$pid" 2>/dev/null || { cat "$file" >&2; die "$what exited during start-up"; }
        [ "$SECONDS" -lt "$deadline" ] || { cat "$file" >&2; die "$what did not start within ${STARTUP_SECONDS}s"; }
        sleep 0.2
    done
}

"$REDOCLY" bundle "$SPEC" -o "$TMP/openapi.json" >"$TMP/bundle.log" 2>&1 || { cat "$TMP/bundle.log" >&2; die "cannot read $SPEC"; }

API_KEY=contract-$RANDOM$RANDOM
"$SERVER" --db "$TMP/locus.db" --host 127.0.0.1 --port 0 --api-key "$API_KEY" --max-body-bytes 65536 \
    >"$TMP/server.out" 2>"$TMP/server.log" &
SERVER_PID=$!
wait_for "$TMP/server.log" '"event":"listening"' "$SERVER_PID" locus-server
SERVER_PORT=$(sed -n 's/.*"event":"listening".*"port":\([0-9]*\).*/\1/p' "$TMP/server.log" | head -n1)
[ -n "$SERVER_PORT" ] || die "cannot read the server's port from its log"

PRISM_PORT=$(node -e 'const s=require("net").createServer();s.listen(0,"127.0.0.1",()=>{console.log(s.address().port);s.close()})')
"$PRISM" proxy "$SPEC" "http://127.0.0.1:$SERVER_PORT" --host 127.0.0.1 --port "$PRISM_PORT" \
    >"$TMP/prism.log" 2>&1 &
PRISM_PID=$!
wait_for "$TMP/prism.log" 'Prism is listening' "$PRISM_PID" Prism

set +e
CONTRACT_PROXY="http://127.0.0.1:$PRISM_PORT" CONTRACT_SERVER="http://127.0.0.1:$SERVER_PORT" CONTRACT_SPEC_JSON="$TMP/openapi.json" \
    CONTRACT_API_KEY="$API_KEY" CONTRACT_SERVER_LOG="$TMP/server.log" NODE_NO_WARNINGS=1 \
    timeout "$RUN_SECONDS" node "$ROOT/scripts/contract_check.mjs"
status=$?
set -e
if [ "$status" -eq 124 ]; then
    echo "contract: timed out after ${RUN_SECONDS}s" >&2
elif [ "$status" -ne 0 ] && [ -n "${CONTRACT_VERBOSE:-}" ]; then
    echo "--- Prism log" >&2; cat "$TMP/prism.log" >&2
fi
exit "$status"
