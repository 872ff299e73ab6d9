# The preamble the tests/deploy/*.sh scripts share; each sources it right after
# `set -euo pipefail`. It gives them:
#   repo            the repository's root
#   tmp             a fresh temporary directory, removed on exit
#   pids            processes to kill on exit: start one in the background, then `pids+=("$!")`
#   exit_hooks      more commands (strings, eval'd) to run on exit, before the kills
#   fail MESSAGE    prints FAIL: MESSAGE and exits 1
#   free_port       a TCP port free on 127.0.0.1 now
#   wait_for_log LOG PATTERN WHAT [PID]
#                   waits up to 10 s for LOG to match the extended regex PATTERN; fails, showing
#                   LOG, when PID (if given) exits first ("WHAT exited") or time runs out
#                   ("WHAT did not start")
#   logged_port LOG the port a locus-server started with --port 0 reports in its log
#   stop_pid PID    kills PID, reaps it and drops it from pids
#   start_replica BIN NAME ARGS...
#                   a locus-server (BIN) on a free port with --db ARGS..., logging to
#                   $tmp/NAME.log (its JSON access log is how a test sees which replica served
#                   what), a 0.2 s heartbeat and nginx on loopback trusted for X-Forwarded-For
#                   as docker/compose.yaml does; sets port and pid (no command substitution:
#                   the server would hold its pipe open)
#   start_nginx_front PORT_1 PORT_2
#                   docker/nginx.conf with docker/nginx-upstream-replicated.conf, replica-1 and
#                   replica-2 at these loopback ports, one worker, on a free port; sets url
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
tmp=$(mktemp -d)
pids=()
exit_hooks=()

deploy_cleanup() {
  local hook p
  for hook in "${exit_hooks[@]}"; do eval "$hook" || true; done
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  rm -rf "$tmp"
}
trap deploy_cleanup EXIT

fail() { echo "FAIL: $*" >&2; exit 1; }

free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

wait_for_log() {
  local log=$1 pattern=$2 what=$3 watched=${4:-}
  for _ in $(seq 100); do
    grep -qE "$pattern" "$log" 2>/dev/null && return 0
    if [ -n "$watched" ] && ! kill -0 "$watched" 2>/dev/null; then
      grep -qE "$pattern" "$log" 2>/dev/null && return 0
      fail "$what exited: $(cat "$log")"
    fi
    sleep 0.1
  done
  fail "$what did not start: $(cat "$log")"
}

logged_port() { grep -o '"port":[0-9]*' "$1" | head -1 | cut -d: -f2; }

stop_pid() {
  local victim=$1 p kept=()
  kill "$victim" 2>/dev/null || true
  wait "$victim" 2>/dev/null || true
  for p in "${pids[@]}"; do [ "$p" = "$victim" ] || kept+=("$p"); done
  pids=("${kept[@]}")
}

start_replica() {
  local bin=$1 name=$2
  shift 2
  "$bin" --db "$@" --host 127.0.0.1 --port 0 --track-heartbeat 0.2 --trusted-proxy 127.0.0.1 >/dev/null 2>"$tmp/$name.log" &
  pid=$!
  pids+=("$pid")
  wait_for_log "$tmp/$name.log" '"port":[0-9]' "replica $name" "$pid"
  port=$(logged_port "$tmp/$name.log")
}

start_nginx_front() {
  local front
  front=$(free_port)
  sed -e "s|/tmp/nginx|$tmp/nginx|g" -e "s|listen 8080;|listen 127.0.0.1:$front;|" \
      -e 's|worker_processes auto;|worker_processes 1;|' "$repo/docker/nginx.conf" >"$tmp/nginx.conf"
  sed -E -e "s/replica-1:8080/127.0.0.1:$1/" -e "s/replica-2:8080/127.0.0.1:$2/" \
      "$repo/docker/nginx-upstream-replicated.conf" >"$tmp/locus-upstream.conf"
  grep -q "127.0.0.1:$2" "$tmp/locus-upstream.conf" || fail "the upstream list no longer names replica-1 and replica-2"
  exit_hooks+=('[ -f "$tmp/nginx.pid" ] && kill "$(cat "$tmp/nginx.pid")" 2>/dev/null')
  nginx -e "$tmp/error.log" -p "$tmp" -c "$tmp/nginx.conf" || fail "nginx did not start: $(cat "$tmp/error.log")"
  url=http://127.0.0.1:$front
  for _ in $(seq 50); do curl -sf "$url/health" >/dev/null && return 0; sleep 0.1; done
  fail "nginx answers no /health: $(cat "$tmp/error.log")"
}
