#!/usr/bin/env bash
# docker/nginx.conf doing its job in front of two real locus-servers on loopback (the shape of
# the replicated compose profile, without docker; each replica on its own SQLite file, which
# is all nginx can tell apart): requests reach both replicas; with one replica killed,
# localize (a POST) and GETs still answer 200, none 502; an event stream's heartbeats come
# through nginx as they are written. (That last check passes with proxy_buffering on as well:
# nginx passes small chunks on to a fast reader either way; buffering off matters for slow
# readers, which this does not simulate.)
# Usage: nginx_proxy_test.sh LOCUS_SERVER_BIN. Exit 77 (skipped) when nginx is not installed.
set -euo pipefail
server_bin=$1
command -v nginx >/dev/null 2>&1 || { echo "nginx not installed (Debian nginx-light): skipped"; exit 77; }
source "$(dirname "$0")/lib.sh"

# Each replica on its own SQLite file.
start_replica "$server_bin" a "$tmp/a.db" --demo; port_a=$port
start_replica "$server_bin" b "$tmp/b.db" --demo; port_b=$port; pid_b=$pid
start_nginx_front "$port_a" "$port_b"

# A localize body from the demo radio map's first RP.
body=$(curl -sf "$url/v1/radiomaps/1/export" | python3 -c '
import json, sys
rp = json.load(sys.stdin)["rps"][0]
print(json.dumps({"scans": [[{"type": m["type"], "bssid": m["bssid"], "rss": m["mean"]} for m in rp["measurements"]]]}))')
localize() { curl -s -o /dev/null -w '%{http_code}\n' -X POST -H 'Content-Type: application/json' -d "$body" "$url/v1/maps/1/localize"; }

# Both replicas take requests: each one's access log (JSON lines on stderr) grows.
for _ in $(seq 20); do [ "$(localize)" = 200 ] || fail "localize through nginx did not answer 200"; done
for name in a b; do grep -q '"/v1/maps/1/localize"' "$tmp/$name.log" || fail "replica $name got no localize request"; done

# One replica dies: nothing fails, the other answers.
kill -9 "$pid_b"; wait "$pid_b" 2>/dev/null || true
codes=$(for _ in $(seq 20); do localize; curl -s -o /dev/null -w '%{http_code}\n' "$url/v1/maps/1"; done | sort | uniq -c)
echo "$codes" | grep -qv ' 200$' && fail "with replica b killed, answers were: $codes"

# Event stream through nginx (the events location): heartbeats every 0.2 s arrive as written.
stream=$(curl -sN --max-time 1.5 "$url/v1/maps/1/positions/events" || true)
beats=$(grep -c '^: heartbeat' <<<"$stream" || true)
[ "$beats" -ge 4 ] || fail "event stream through nginx: $beats heartbeats in 1.5 s, want at least 4"

echo "ok: both replicas served, no error with one killed, event stream live ($beats heartbeats in 1.5 s)"
