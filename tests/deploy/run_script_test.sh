#!/usr/bin/env bash
# scripts/run.sh as the README promises: its own defaults give way to the server flags a user
# passes (`./scripts/run.sh --port 9090`), and the environment overrides still work. Runs the
# binaries already built (LOCUS_NO_BUILD=1), so it never touches the build.
# Usage: run_script_test.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/lib.sh"
build_dir=$1

# Starts run.sh with the given environment and arguments; waits until it listens on $port.
start() {
  env LOCUS_NO_BUILD=1 LOCUS_BUILD_DIR="$build_dir" "$@" >/dev/null 2>"$tmp/log" &
  pid=$!
  pids+=("$pid")
  wait_for_log "$tmp/log" '"event":"listening"' run.sh "$pid"
}
stop() { stop_pid "$pid"; }
health() { python3 -c "import urllib.request,sys; print(urllib.request.urlopen('http://127.0.0.1:$1/health').status)"; }

port=$(free_port)
start "$repo/scripts/run.sh" --port "$port" --db "$tmp/a.db" --quiet
grep -q "\"port\":$port" "$tmp/log" || fail "--port $port was not the port served: $(cat "$tmp/log")"
[ "$(health "$port")" = 200 ] || fail "no /health on $port"
[ -f "$tmp/a.db" ] || fail "--db was not used"
stop

port=$(free_port)
start LOCUS_PORT="$port" LOCUS_DB="$tmp/b.db" "$repo/scripts/run.sh" --quiet
[ "$(health "$port")" = 200 ] || fail "LOCUS_PORT=$port not served"
[ -f "$tmp/b.db" ] || fail "LOCUS_DB was not used"
stop

port=$(free_port)
start LOCUS_PORT=1 "$repo/scripts/run.sh" "--port=$port" "--db=$tmp/c.db" --quiet
[ "$(health "$port")" = 200 ] || fail "--port=$port did not win over LOCUS_PORT"
stop
echo "run.sh: flags and environment as documented"
