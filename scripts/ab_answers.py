#!/usr/bin/env python3
"""Compares two locus-server binaries answer by answer: the check behind a "no behaviour
change" claim (a reshape, a second storage backend).

    scripts/ab_answers.py OLD_SERVER_BIN NEW_SERVER_BIN [--mutations N] [--seed S]

Starts each binary with --demo on its own temporary database on a free 127.0.0.1 port, sends
both the same requests (CRUD on every kind, scan uploads, export and import, localize with
every algorithm, and N seeded mutations of valid bodies for each write and localize route),
and prints every request whose status or body differs. Exit status 1 when any differs.
Standard library only; loopback only.
"""
import argparse
import copy
import http.client
import json
import os
import random
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

    def call(self, method, path, body=None):
        conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=30)
        data = body if isinstance(body, (bytes, type(None))) else json.dumps(body).encode()
        headers = {"Content-Type": "application/json"} if data is not None else {}
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


def run(server, reqs):
    out = []
    ids = {}
    for method, path, body in reqs:
        path = path.format(**{k: ids.get(k, 0) for k in ("rp", "room", "poi")})
        status, text = server.call(method, path, body)
        if method == "POST" and status == 201 and path.endswith("/rps") and "rp" not in ids:
            ids["rp"] = json.loads(text)["id"]
        out.append((method, path, json.dumps(body) if not isinstance(body, bytes) else repr(body), status, text))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--mutations", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    reqs = scenario(args.mutations, args.seed)
    results = []
    for binary in (args.old, args.new):
        with tempfile.TemporaryDirectory() as tmp:
            server = Server(binary, tmp)
            try:
                results.append(run(server, reqs))
            finally:
                server.stop()
    differ = 0
    for a, b in zip(*results):
        if a[3:] != b[3:]:
            differ += 1
            print(f"DIFF {a[0]} {a[1]} {a[2][:300]}\n  old {a[3]} {a[4][:400]}\n  new {b[3]} {b[4][:400]}")
    statuses = {}
    for r in results[1]:
        statuses[r[3]] = statuses.get(r[3], 0) + 1
    print(f"ab_answers: {len(reqs)} requests, {differ} differ; statuses {dict(sorted(statuses.items()))}")
    sys.exit(1 if differ else 0)


if __name__ == "__main__":
    main()
