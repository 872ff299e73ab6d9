#!/usr/bin/env bash
# `cmake --install` as docs/deploy.md's single-node section uses it, into a temporary prefix:
# locus-server, locus, the web viewer, the systemd unit (which systemd-analyze accepts, and
# whose ExecStart names the installed server and environment file) and its user; the
# installed server serves the viewer from the prefix; a second install keeps the operator's
# environment file.
# Usage: install_test.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/lib.sh"
build_dir=$1

prefix=$tmp/prefix
cmake --install "$build_dir" --prefix "$prefix" >"$tmp/install.log" || fail "cmake --install failed: $(cat "$tmp/install.log")"
for f in bin/locus-server bin/locus share/locus/web/index.html lib/systemd/system/locus-server.service \
         lib/sysusers.d/locus-server.conf etc/locus/locus-server.env; do
  [ -e "$prefix/$f" ] || fail "$f was not installed"
done
unit=$prefix/lib/systemd/system/locus-server.service
grep -q "^ExecStart=$prefix/bin/locus-server --db /var/lib/locus/locus.db" "$unit" || fail "ExecStart: $(grep ExecStart "$unit")"
grep -q "^EnvironmentFile=-$prefix/etc/locus/locus-server.env$" "$unit" || fail "EnvironmentFile: $(grep EnvironmentFile "$unit")"
grep -q "^User=locus$" "$unit" || fail "the unit does not run as its own user"
[ "$(stat -c %a "$prefix/etc/locus/locus-server.env")" = 600 ] || fail "the environment file (the API key) is not 0600"
if command -v systemd-analyze >/dev/null 2>&1; then
  # verify checks the unit's syntax and that ExecStart's binary exists.
  out=$(systemd-analyze verify --man=no "$unit" 2>&1 || true)
  echo "$out" | grep -v "Cannot add dependency job\|network-online.target\|not found\|Failed to prepare" | grep -qi "error\|unknown" \
    && fail "systemd-analyze verify: $out"
fi
grep -q '^u locus ' "$prefix/lib/sysusers.d/locus-server.conf" || fail "no sysusers line for the locus user"

# The installed server finds the web viewer under the prefix.
"$prefix/bin/locus-server" --db "$tmp/locus.db" --port 0 --demo --quiet 2>"$tmp/server.log" &
pids+=("$!")
wait_for_log "$tmp/server.log" '"port":[0-9]' "the installed server" "$!"
port=$(logged_port "$tmp/server.log")
python3 - "$port" <<'PY' || fail "the installed server does not serve the viewer"
import sys, urllib.request
body = urllib.request.urlopen(f"http://127.0.0.1:{sys.argv[1]}/").read().decode()
assert "<html" in body.lower(), body[:200]
PY
"$prefix/bin/locus" --help >/dev/null || fail "the installed locus does not run"

# A second install keeps the operator's settings.
echo "LOCUS_API_KEY=operators-own" >>"$prefix/etc/locus/locus-server.env"
cmake --install "$build_dir" --prefix "$prefix" >/dev/null
grep -q "operators-own" "$prefix/etc/locus/locus-server.env" || fail "a second install overwrote the environment file"
echo "install: binaries, viewer, systemd unit and user, environment file ok"
