#!/usr/bin/env bash
# docker/nginx.conf's routing of live tracks, in front of two real locus-servers sharing one
# PostgreSQL database (the replicated compose profile's shape, without docker): every request
# of a track (its thin client's /steps, its GET) reaches one replica, by a consistent hash on
# the track id, and the tracks spread over both; with a track's replica killed by kill -9
# between two batches, its next /steps answers 200 from the other replica, which resumes the
# filter at the track's latest stored fix (the answer's first fused fix comes after it), and
# no other track's request fails.
# Usage: nginx_tracks_test.sh LOCUS_SERVER_BIN. Exit 77 (skipped) without nginx or without
# LOCUS_TEST_DB_URL (scripts/with_postgres.sh sets it).
set -euo pipefail
server_bin=$1
command -v nginx >/dev/null 2>&1 || { echo "nginx not installed (Debian nginx-light): skipped"; exit 77; }
[ -n "${LOCUS_TEST_DB_URL:-}" ] || { echo "LOCUS_TEST_DB_URL unset (run under scripts/with_postgres.sh): skipped"; exit 77; }
source "$(dirname "$0")/lib.sh"
command -v psql >/dev/null 2>&1 || fail "psql not found (Debian postgresql-client)"

# A database of this test's own on the throwaway cluster (with_postgres.sh deletes it all).
db=nginx_tracks_$$
psql "$LOCUS_TEST_DB_URL" -qc "CREATE DATABASE $db" >/dev/null || fail "could not create database $db"
db_url=${LOCUS_TEST_DB_URL%/*}/$db
# One replica creates the demo map (and runs the migrations) before the other starts.
start_replica "$server_bin" a "$db_url" --demo; port_a=$port; pid_a=$pid
start_replica "$server_bin" b "$db_url"; port_b=$port; pid_b=$pid
start_nginx_front "$port_a" "$port_b"

python3 - "$url" "$tmp" "$pid_a" "$pid_b" <<'PY'
import json, os, re, signal, sys, time, urllib.error, urllib.request

url, tmp, pids = sys.argv[1], sys.argv[2], {"a": int(sys.argv[3]), "b": int(sys.argv[4])}

def fail(msg):
    sys.exit("FAIL: " + msg)

def call(method, path, body=None, token=None):
    req = urllib.request.Request(url + path, method=method, data=None if body is None else json.dumps(body).encode())
    req.add_header("Content-Type", "application/json")
    if token:
        req.add_header("X-Track-Token", token)
    try:
        with urllib.request.urlopen(req, timeout=10) as r:
            return r.status, json.loads(r.read() or b"null")
    except urllib.error.HTTPError as e:
        return e.code, e.read().decode(errors="replace")

def served(name, track):
    """How many of this track's requests replica `name` logged."""
    pattern = re.compile(r'"/v1/tracks/%d(/[a-z]+)?"' % track)
    with open(os.path.join(tmp, name + ".log")) as f:
        return sum(1 for line in f if pattern.search(line))

def settled(count, want):
    """count(), given up to 5 s to reach `want`: a replica logs a request after it has answered
    it, so on a busy machine the line can come after the answer."""
    deadline = time.monotonic() + 5
    while True:
        n = count()
        if n >= want or time.monotonic() > deadline:
            return n
        time.sleep(0.05)

# Fixes at the demo radio map's RPs, on their floor.
status, export = call("GET", "/v1/radiomaps/1/export")
if status != 200:
    fail(f"radio map export answered {status}: {export}")
rps = export["rps"]
floor = export.get("floor_id") or rps[0].get("floor_id")

start = time.time() - 60.0

def batch(k):
    """Batch k of a walk: 4 steps of 0.7 m heading east, then a fix at an RP."""
    t0 = start + 4 * k
    rp = rps[k % len(rps)]
    steps = [{"t": t0 + i, "length_m": 0.7, "heading_deg": 90.0} for i in range(1, 5)] if k else []
    return {"steps": steps, "fixes": [{"t": t0 + 4, "floor_id": floor, "x": rp["x"], "y": rp["y"], "accuracy_m": 2.0}]}

tracks = []
for _ in range(16):
    status, opened = call("POST", "/v1/tracks", {"map_id": 1})
    if status != 201:
        fail(f"opening a track through nginx answered {status}: {opened}")
    tracks.append((opened["id"], opened["token"]))

def walk(track, token, ks):
    for k in ks:
        status, answer = call("POST", f"/v1/tracks/{track}/steps", batch(k), token)
        if status != 200:
            fail(f"track {track}'s batch {k} answered {status}: {answer}")
    status, got = call("GET", f"/v1/tracks/{track}", token=token)
    if status != 200:
        fail(f"GET track {track} answered {status}: {got}")
    return answer

for track, token in tracks:
    walk(track, token, range(3))
home = {}
for track, _ in tracks:
    settled(lambda: sum(served(name, track) for name in pids), 4)
    counts = {name: served(name, track) for name in pids}
    if min(counts.values()) != 0 or max(counts.values()) != 4:
        fail(f"track {track}'s 4 requests were served {counts}: want all by one replica")
    home[track] = max(counts, key=counts.get)
if len(set(home.values())) != 2:
    fail(f"all 16 tracks went to replica {set(home.values())}: the hash should spread them")

# The replica of the first track on b dies between two batches: that track's next batch and
# every other track's go on, each on its own replica or, for b's, on a.
os.kill(pids["b"], signal.SIGKILL)
moved = [t for t in tracks if home[t[0]] == "b"]
for track, token in tracks:
    before = served("a", track)
    answer = walk(track, token, [3])
    fused = [f["t"] for f in answer["fused"]]
    if not fused or min(fused) <= start + 4 * 2 + 4:
        fail(f"track {track}'s batch after the kill fused {fused}: want fixes after the latest stored one")
    if home[track] == "b" and settled(lambda: served("a", track), before + 2) - before != 2:
        fail(f"track {track} (on b) was not taken over by a after b died")
print(f"ok: 16 tracks each on one replica ({sum(1 for h in home.values() if h == 'a')} on a), "
      f"{len(moved)} taken over by a after b was killed, no request failed")
PY
