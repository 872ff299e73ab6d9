#!/usr/bin/env python3
"""Compares two locus-server binaries answer by answer: the check behind a "no behaviour
change" claim (a reshape, a second storage backend).

    scripts/ab_answers.py OLD_SERVER_BIN NEW_SERVER_BIN [--mutations N] [--seed S]

Starts each binary with --demo on its own temporary database on a free 127.0.0.1 port, sends
both the same requests, one to each in turn (CRUD on every kind, scan uploads, export and
import, localize with every algorithm, transmitters with their fit, generated radio maps,
tuning, routes and the directory, live tracks with fixes, thin-client steps, shares,
relative positions and event streams, and N seeded mutations of valid bodies for each write,
localize and track route), and prints every request whose status or body differs. What the
two servers cannot share is masked before comparing: track and share tokens, and times taken
from the server's clock (created_at, last_fix_at, ended_at, age_s, took_ms). Exit status 1
when any differs. Standard library only; loopback only.
"""
import argparse
import copy
import http.client
import json
import os
import random
import re
import signal
import socket
import subprocess
import sys
import tempfile
import time

ALGORITHMS = ["bsb", "nn", "bsbnn", "knn", "wknn", "bayes"]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Server:
    def __init__(self, binary, workdir):
        self.port = free_port()
        self.db = os.path.join(workdir, "ab.db")
        self.proc = subprocess.Popen([binary, "--db", self.db, "--port", str(self.port), "--demo", "--quiet"],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.time() + 30
        while time.time() < deadline:
            try:
                if self.call("GET", "/health")[0] == 200:
                    return
            except OSError:
                time.sleep(0.05)
        raise SystemExit(f"{binary} did not start")

    def call(self, method, path, body=None, headers=None):
        conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=30)
        data = body if isinstance(body, (bytes, type(None))) else json.dumps(body).encode()
        headers = dict(headers or {})
        if data is not None:
            headers["Content-Type"] = "application/json"
        conn.request(method, path, body=data, headers=headers)
        r = conn.getresponse()
        out = (r.status, r.read().decode("utf-8", "replace"))
        conn.close()
        return out

    def stop(self):
        self.proc.send_signal(signal.SIGTERM)
        self.proc.wait(timeout=30)


def mutate(value, rng):
    """One random structural change somewhere in a JSON value."""
    choices = [None, True, -1, 0, 1.5, 1e308, -1e308, "", "x" * 300, "AA-BB-CC-DD-EE-FF", [], {}, -121, 0.0001]
    if isinstance(value, (dict, list)) and value and rng.random() < 0.8:
        key = rng.choice(list(value)) if isinstance(value, dict) else rng.randrange(len(value))
        r = rng.random()
        if r < 0.2:
            del value[key]
        elif r < 0.3 and isinstance(value, dict):
            value["unknown_" + key] = value[key]
        elif r < 0.3:
            value.append(copy.deepcopy(value[key]))
        elif r < 0.65:
            value[key] = mutate(value[key], rng)
        else:
            value[key] = rng.choice(choices)
        return value
    return rng.choice(choices)


def scenario(mutations, seed):
    """The requests, as (method, path, body) in order; later ones depend on earlier writes."""
    rng = random.Random(seed)
    reqs = []
    for kind in ["maps", "buildings", "floors", "rooms", "pois", "radiomaps", "rps"]:
        reqs.append(("GET", f"/v1/{kind}/1", None))
    reqs += [("GET", "/v1/maps", None), ("GET", "/v1/maps/1/buildings", None), ("GET", "/v1/buildings/1/floors", None),
             ("GET", "/v1/floors/1/rooms", None), ("GET", "/v1/floors/1/pois?limit=2&offset=1", None),
             ("GET", "/v1/floors/1/radiomaps", None), ("GET", "/v1/radiomaps/1/rps?limit=5", None),
             ("GET", "/v1/radiomaps/1/export", None)]
    creates = [
        ("/v1/maps", {"name": "AB", "description": "a/b"}),
        ("/v1/maps/2/buildings", {"name": "B"}),
        ("/v1/buildings/2/floors", {"name": "F", "level": 3, "width": 40.5, "height": 20, "north_offset_deg": 12}),
        ("/v1/floors/3/rooms", {"name": "R", "rects": [{"xmin": 0, "ymin": 0, "xmax": 5, "ymax": 4}]}),
        ("/v1/floors/3/pois", {"name": "P", "kind": "exit", "x": 1, "y": 2}),
        ("/v1/floors/3/radiomaps", {"name": "RM"}),
        ("/v1/radiomaps/3/rps", {"name": "rp", "x": 3, "y": 3.25}),
    ]
    for path, body in creates:
        reqs.append(("POST", path, body))
        for _ in range(mutations // 10):
            reqs.append(("POST", path, mutate(copy.deepcopy(body), rng)))
    patches = [("/v1/maps/2", {"description": None}), ("/v1/floors/3", {"width": 41, "level": 2.0}),
               ("/v1/rooms/{room}", {"rects": [{"xmin": 1, "ymin": 1, "xmax": 2, "ymax": 2}, {"xmin": 2, "ymin": 1, "xmax": 3, "ymax": 2}]}),
               ("/v1/pois/{poi}", {"kind": None, "x": -5})]
    upload = {"upload_id": "u1", "scans": [[{"bssid": "AA-BB-CC-DD-EE-01", "rss": -50}, {"type": "ble", "bssid": "b1", "rss": -70}],
                                            [{"bssid": "aa:bb:cc:dd:ee:01", "rss": -54}]]}
    aggregates = {"measurements": [{"bssid": "x", "mean": -60, "variance": 2, "count": 3},
                                   {"bssid": "X ", "mean": -64, "variance": 0, "count": 1}]}
    reqs.append(("PATCH", "/v1/maps/2", patches[0][1]))
    reqs.append(("PATCH", "/v1/floors/3", patches[1][1]))
    reqs.append(("GET", "/v1/floors/3/rooms", None))
    reqs.append(("POST", "/v1/rps/{rp}/scans", upload))
    reqs.append(("POST", "/v1/rps/{rp}/scans", upload))
    reqs.append(("POST", "/v1/rps/{rp}/scans", aggregates))
    for body in (upload, aggregates):
        for _ in range(mutations):
            reqs.append(("POST", "/v1/rps/{rp}/scans", mutate(copy.deepcopy(body), rng)))
    reqs.append(("GET", "/v1/radiomaps/3/export", None))
    doc = {"format": "locus-radiomap/1", "name": "imported", "description": None,
           "rps": [{"name": "a", "x": 1, "y": 1, "scans": 2, "measurements": [
               {"type": "wifi", "bssid": "AA-BB-CC-DD-EE-02", "mean": -40, "variance": 1, "count": 2},
               {"type": None, "bssid": "c", "mean": -80, "variance": 0, "count": 1}]},
               {"name": "b", "x": 9, "y": 4}]}
    reqs.append(("POST", "/v1/floors/1/radiomaps/import", doc))
    for i in range(mutations):
        d = mutate(copy.deepcopy(doc), rng)
        if isinstance(d, dict):
            d["name"] = f"imported-{i}"
        reqs.append(("POST", "/v1/floors/1/radiomaps/import", d))
    # Localize with APs of the demo radio map.
    scans = [[{"bssid": "00:1a:2b:00:00:01", "rss": -48}, {"bssid": "00:1a:2b:00:00:02", "rss": -71},
              {"bssid": "00-1A-2B-00-00-03", "rss": -68}], [{"bssid": "00:1a:2b:00:00:01", "rss": -52}]]
    for algorithm in ALGORITHMS:
        for scope in ("radiomaps/1", "maps/1"):
            reqs.append(("POST", f"/v1/{scope}/localize", {"algorithm": algorithm, "scans": scans}))
            reqs.append(("POST", f"/v1/{scope}/localize",
                         {"algorithm": algorithm, "scans": scans, "options": {"k": 2, "near": {"x": 5, "y": 5, "radius": 20}}}))
    base = {"algorithm": "wknn", "scans": scans, "options": {"k": 3}}
    for _ in range(mutations):
        reqs.append(("POST", "/v1/radiomaps/1/localize", mutate(copy.deepcopy(base), rng)))
    for raw in [b"", b"{", b"[]", b"{\"scans\":[[]]}", b"\x00", "{\"name\":\"\u00e9\"}".encode()]:
        reqs.append(("POST", "/v1/maps", raw))
        reqs.append(("POST", "/v1/radiomaps/1/localize", raw))
    reqs += [("GET", "/v1/maps/0", None), ("GET", "/v1/maps/99999999999999999999", None), ("GET", "/v1/nothing", None),
             ("DELETE", "/v1/radiomaps/1", None), ("POST", "/v1/radiomaps/1/localize", {"scans": scans}),
             ("POST", "/v1/maps/1/localize", {"scans": scans}), ("DELETE", "/v1/maps/2", None), ("GET", "/v1/floors/3", None),
             ("GET", "/v1/maps", None)]
    return reqs


DEMO_APS = [("00:1a:2b:00:00:01", 4, 4), ("00:1a:2b:00:00:02", 26, 4), ("00:1a:2b:00:00:03", 15, 13),
            ("00:1a:2b:00:00:04", 8, 11)]


def services_scenario():
    """Transmitters, their fit, generated radio maps, tuning, routes and the directory on the demo map."""
    reqs = []
    for bssid, x, y in DEMO_APS:
        reqs.append(("POST", "/v1/floors/1/transmitters", {"type": "wifi", "bssid": bssid, "x": x, "y": y, "tx_power": -40}))
    reqs.append(("POST", "/v1/floors/1/transmitters", {"type": "wifi", "bssid": "x", "x": "1", "y": 1}))
    reqs.append(("GET", "/v1/floors/1/transmitters", None))
    for path in ("/v1/floors/1/transmitters/fit", "/v1/floors/1/transmitters/fit?apply=maybe",
                 "/v1/floors/999/transmitters/fit"):
        reqs.append(("POST", path, {}))
    reqs += [("POST", "/v1/floors/1/transmitters/fit", {"min_rps": 2}),
             ("POST", "/v1/floors/1/transmitters/fit", {"colour": 1}),
             ("POST", "/v1/floors/1/transmitters/fit?apply=true", {}),
             ("GET", "/v1/floors/1/transmitters", None)]
    scan = [{"bssid": b, "rss": -40 - 20 * ((x - 12) ** 2 + (y - 7) ** 2) ** 0.5 / 10} for b, x, y in DEMO_APS]
    for algorithm in ("trilateration", "multilateration"):
        reqs.append(("POST", "/v1/maps/1/localize", {"algorithm": algorithm, "measurements": scan}))
    for body in ({"name": "Model", "step": 2.0}, {"name": "Model", "step": 0}, {"step": 2.0, "sigma_db": 3.0}, {"name": 5}):
        reqs.append(("POST", "/v1/floors/1/radiomaps/generate", body))
    reqs += [("POST", "/v1/radiomaps/1/tune", {"folds": 3}), ("POST", "/v1/radiomaps/1/tune", {"folds": 1}),
             ("POST", "/v1/radiomaps/1/tune", {"colour": 1}), ("GET", "/v1/radiomaps/1", None),
             ("GET", "/v1/radiomaps/1/quality", None), ("POST", "/v1/radiomaps/1/densify", {}),
             ("POST", "/v1/maps/1/route", {"from": {"room_id": 1}, "to": {"room_id": 4}}),
             ("POST", "/v1/maps/1/route", {"from": {"x": 2, "y": 2, "floor_id": 1}, "to": {"x": 20, "y": 12, "floor_id": 2}}),
             ("POST", "/v1/maps/1/route", {"from": {"room_id": 999}}),
             ("GET", "/v1/maps/1/search?q=lab", None), ("GET", "/v1/maps/1/search?q=cafetera&limit=3", None),
             ("GET", "/v1/maps/1/search?q=", None)]
    return reqs


def tracks_scenario(mutations, rng, t0):
    """Live tracks: open, fixes, thin-client steps, shares, relative, streams of closed tracks, close, delete.
    `t0` is a time a little in the past, the same for both servers."""
    own = {"X-Track-Token": "{token}"}
    reqs = [("POST", "/v1/tracks", {"map_id": 1, "label": "a"}), ("POST", "/v1/tracks", {"map_id": 1, "label": "b", "fusion": "kalman_seed"}),
            ("POST", "/v1/tracks", {"map_id": 1, "fusion": "particle"}), ("POST", "/v1/tracks", {"map_id": 999}),
            ("POST", "/v1/tracks", {"map_id": 1, "fusion": "ekf_ranging", "fusion_options": {"huber_k": 2}}),
            ("POST", "/v1/tracks", {"map_id": 1, "fusion": "kalman_ranging"}),
            ("POST", "/v1/tracks", {"map_id": 1, "fusion": "ekf_ranging", "fusion_options": {"huber_k": -1}})]
    readings = [{"bssid": "00:1a:2b:00:00:01", "rss": -48}, {"bssid": "00:1a:2b:00:00:02", "rss": -70},
                {"bssid": "00:1a:2b:00:00:03", "rss": -66}]
    steps = {"steps": [{"t": t0 + 1 + 0.5 * i, "length_m": 0.7, "heading_deg": 80 + i} for i in range(8)],
             "scans": [{"t": t0, "readings": readings}, {"t": t0 + 3, "readings": readings[:2]}]}
    fixes = {"fixes": [{"t": t0 + 10 + i, "floor_id": 1, "x": 3 + i, "y": 4, "accuracy_m": 2, "heading_deg": 90} for i in range(3)]}
    reqs += [("POST", "/v1/tracks/{track}/steps", steps, own), ("POST", "/v1/tracks/{track}/steps", steps, own),
             ("POST", "/v1/tracks/{track}/fixes", fixes, own), ("POST", "/v1/tracks/{track}/fixes", fixes, {}),
             ("POST", "/v1/tracks/{track}/fixes", fixes, {"X-Track-Token": "trk_wrong"}),
             ("POST", "/v1/tracks/{track2}/steps", steps, {"X-Track-Token": "{token2}"}),
             ("POST", "/v1/tracks/{track2}/steps", dict(steps, scans=[], fixes=[{"t": t0, "floor_id": 1, "x": 4, "y": 4, "accuracy_m": 2}]),
              {"X-Track-Token": "{token2}"}),
             ("POST", "/v1/tracks/{track2}/fixes", {"fixes": [{"t": t0 + 20, "floor_id": 2, "x": 20, "y": 12, "accuracy_m": 3}]},
              {"X-Track-Token": "{token2}"})]
    for n in (3, 4, 5):
        reqs.append(("POST", f"/v1/tracks/{{track{n}}}/steps", steps, {"X-Track-Token": f"{{token{n}}}"}))
        reqs.append(("POST", f"/v1/tracks/{{track{n}}}/steps", dict(steps, scans=[], fixes=[{"t": t0 + 9, "floor_id": 1, "x": 9, "y": 5, "accuracy_m": 2}]),
                     {"X-Track-Token": f"{{token{n}}}"}))
    for body in (steps, fixes):
        route = "steps" if body is steps else "fixes"
        for _ in range(mutations // 4):
            reqs.append(("POST", "/v1/tracks/{track}/" + route, mutate(copy.deepcopy(body), rng), own))
    reqs += [("GET", "/v1/tracks/{track}", None, own), ("GET", "/v1/tracks/{track}?limit=2", None, own),
             ("GET", "/v1/tracks/{track}?limit=0", None, own), ("GET", "/v1/tracks/{track}?token={token}", None),
             ("POST", "/v1/tracks/{track2}/shares", {}, {"X-Track-Token": "{token2}"}),
             ("GET", "/v1/tracks/{track2}", None, {"X-Track-Token": "{share_token}"}),
             ("GET", "/v1/tracks/{track}/relative/{track2}", None, {"X-Track-Token": "{token}", "X-Peer-Token": "{share_token}"}),
             ("GET", "/v1/tracks/{track}/relative/{track2}", None, {"X-Track-Token": "{token}"}),
             ("GET", "/v1/tracks/{track}/relative/{track2}", None, {"X-Track-Token": "{token}", "X-Peer-Token": "{token}"}),
             ("GET", "/v1/maps/1/positions", None), ("GET", "/v1/maps/1/positions?floor_id=2", None),
             ("GET", "/v1/maps/1/positions?floor_id=x", None),
             ("DELETE", "/v1/tracks/{track2}/shares/{share}", None, {"X-Track-Token": "{token2}"}),
             ("GET", "/v1/tracks/{track2}", None, {"X-Track-Token": "{share_token}"}),
             ("POST", "/v1/tracks/{track}/close", None, own), ("POST", "/v1/tracks/{track}/fixes", fixes, own),
             ("GET", "/v1/tracks/{track}/events", None, own), ("GET", "/v1/tracks/{track}", None, own),
             ("DELETE", "/v1/tracks/{track}", None, own), ("GET", "/v1/tracks/{track}", None, own),
             ("DELETE", "/v1/tracks/{track2}", None, {"X-Track-Token": "{token2}"})]
    return reqs


# Values the two servers cannot share: tokens, and times read from each server's own clock.
MASKED_KEYS = {"token", "created_at", "last_fix_at", "ended_at", "age_s", "last_upload_at", "updated_at", "seconds"}
TOKEN = re.compile(r"\b(trk|shr)_[0-9a-f]{16,}")


def masked(text):
    def walk(v):
        if isinstance(v, dict):
            return {k: ("*" if k in MASKED_KEYS else walk(x)) for k, x in v.items()}
        if isinstance(v, list):
            return [walk(x) for x in v]
        return v
    text = TOKEN.sub(lambda m: m.group(1) + "_*", text)
    try:
        return json.dumps(walk(json.loads(text)), sort_keys=True)
    except ValueError:
        return text  # event streams, plain-text errors


class Session:
    """One server and the ids its answers gave, for the later requests' paths and headers."""
    def __init__(self, server):
        self.server, self.ids = server, {}

    def fill(self, text):
        return re.sub(r"\{(\w+)\}", lambda m: str(self.ids.get(m.group(1), 0)), text)

    def send(self, method, path, body, headers):
        path = self.fill(path)
        headers = {k: self.fill(v) for k, v in (headers or {}).items()}
        status, text = self.server.call(method, path, body, headers)
        if method == "POST" and status == 201:
            answer = json.loads(text)
            if path.endswith("/rps") and "rp" not in self.ids:
                self.ids["rp"] = answer["id"]
            elif path == "/v1/tracks":
                n = sum(k.startswith("track") for k in self.ids) + 1
                suffix = "" if n == 1 else str(n)
                self.ids["track" + suffix], self.ids["token" + suffix] = answer["id"], answer["token"]
            elif path.endswith("/shares"):
                self.ids["share"], self.ids["share_token"] = answer["id"], answer["token"]
        return path, status, masked(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--mutations", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    rng = random.Random(args.seed + 1)
    reqs = [r + (None,) for r in scenario(args.mutations, args.seed)]
    reqs[-9:-9] = [r + (None,) if len(r) == 3 else r for r in services_scenario() + tracks_scenario(args.mutations, rng, int(time.time()) - 600)]
    differ, statuses = 0, {}
    with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
        servers = [Server(args.old, a), Server(args.new, b)]
        try:
            sessions = [Session(s) for s in servers]
            for method, path, body, headers in reqs:
                old, new = (s.send(method, path, body, headers) for s in sessions)
                statuses[new[1]] = statuses.get(new[1], 0) + 1
                if old[1:] != new[1:]:
                    differ += 1
                    shown = json.dumps(body) if not isinstance(body, bytes) else repr(body)
                    print(f"DIFF {method} {old[0]} {shown[:300]}\n  old {old[1]} {old[2][:400]}\n  new {new[1]} {new[2][:400]}")
        finally:
            for s in servers:
                s.stop()
    print(f"ab_answers: {len(reqs)} requests, {differ} differ; statuses {dict(sorted(statuses.items()))}")
    sys.exit(1 if differ else 0)


if __name__ == "__main__":
    main()
