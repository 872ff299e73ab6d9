#!/usr/bin/env python3
"""First paint of a big floor in the web viewer, in Debian's headless Chromium: a 60 m x 40 m
floor with 1,000 RPs (8 APs each) and a 3,000 x 2,000 px plan image, served by a real
locus-server on 127.0.0.1 with a fresh database. Measures, per page load, the time from the
navigation's start to the floor drawn (every RP marker added) and its plan image decoded;
prints each run and the median. A measurement to report, not a test.

    scripts/viewer_first_paint.py [--server build/bin/locus-server] [--runs 5]
"""
import argparse
import json
import math
import os
import random
import statistics
import struct
import sys
import urllib.request
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "browser"))
from viewer_test import Server, start_browser  # noqa: E402  (the same server and browser set-up)


def png(width, height):
    """A grey plan drawing: walls every 5 m (100 px at 0.02 m/px), light floor elsewhere."""
    rows = []
    for y in range(height):
        wall_row = y % 100 < 4
        row = bytearray(b"\x00")  # filter: none
        line = bytearray(b"\xf0" * width)
        if wall_row:
            line[:] = b"\x30" * width
        else:
            for x in range(0, width, 100):
                line[x:x + 4] = b"\x30\x30\x30\x30"
        rows.append(bytes(row + line))
    raw = zlib.compress(b"".join(rows), 6)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
            + chunk(b"IDAT", raw) + chunk(b"IEND", b""))


def request(url, method="GET", body=None, content_type="application/json"):
    data = body if isinstance(body, bytes) or body is None else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, method=method, headers={"Content-Type": content_type})
    with urllib.request.urlopen(req, timeout=60) as r:
        text = r.read()
        return json.loads(text) if text else None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--server", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "bin", "locus-server"))
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--accept-encoding", help="send this Accept-Encoding instead of Chromium's own (gzip, deflate, br)")
    args = parser.parse_args()

    server = Server(args.server)
    driver = None
    try:
        u = server.url
        # The demo map comes first (--demo); this floor gets its own map.
        m = request(f"{u}/v1/maps", "POST", {"name": "First paint"})["id"]
        b = request(f"{u}/v1/maps/{m}/buildings", "POST", {"name": "Big building"})["id"]
        f = request(f"{u}/v1/buildings/{b}/floors", "POST", {"name": "Hall", "level": 0, "width": 60, "height": 40})["id"]
        rng = random.Random(7)
        aps = [(f"00:1a:2b:00:10:{i:02x}", rng.uniform(0, 60), rng.uniform(0, 40)) for i in range(8)]
        rps = []
        for i in range(1000):
            x, y = (i % 40) * 1.5 + 0.75, (i // 40) * 1.6 + 0.8
            meas = [{"bssid": bssid, "type": "wifi", "mean": round(-40 - 20 * math.log10(1 + math.hypot(x - ax, y - ay)), 1),
                     "variance": 4.0, "count": 20} for bssid, ax, ay in aps]
            rps.append({"name": f"rp-{i:04d}", "x": x, "y": y, "scans": 20, "measurements": meas})
        request(f"{u}/v1/floors/{f}/radiomaps/import", "POST", {"format": "locus-radiomap/1", "name": "dense", "rps": rps})
        image = png(3000, 2000)
        request(f"{u}/v1/floors/{f}/image?metres_per_pixel=0.02", "PUT", image, "image/png")
        print(f"floor {f}: 1000 RPs, 3000 x 2000 px PNG ({len(image) // 1024} KiB)")

        driver = start_browser(1280, 800)
        driver.set_script_timeout(30)
        if args.accept_encoding:
            driver.execute_cdp_cmd("Network.enable", {})
            driver.execute_cdp_cmd("Network.setExtraHTTPHeaders", {"headers": {"Accept-Encoding": args.accept_encoding}})
        times = []
        for run in range(args.runs + 1):  # the first load warms Chromium's caches and is not counted
            driver.get(f"{u}/")
            driver.execute_script("window.scrollTo(0, 0)")
            # Choose the big map's floor through the pickers, then time a fresh load of it.
            ms = driver.execute_async_script(f"""
                const done = arguments[arguments.length - 1];
                const start = performance.now();
                const waitFor = (cond) => new Promise((res) => {{ const t = () => cond() ? res() : requestAnimationFrame(t); t(); }});
                (async () => {{
                  await waitFor(() => document.body.dataset.floorReady === 'true');
                  const sel = document.getElementById('map-select');
                  sel.value = '{m}';
                  const t0 = performance.now();
                  const marks = {{}};
                  const plain = window.fetch;
                  window.fetch = async (...a) => {{ const r = await plain(...a); marks[String(a[0]).split('?')[0]] = Math.round(performance.now() - t0); return r; }};
                  sel.dispatchEvent(new Event('change'));
                  await waitFor(() => window.locusViewer.state.floor && window.locusViewer.state.floor.id === {f}
                    && document.body.dataset.floorReady === 'true'
                    && document.querySelectorAll('.rp-marker').length === 1000);
                  marks.drawn = Math.round(performance.now() - t0);
                  const img = document.querySelector('img.leaflet-image-layer');
                  await img.decode();
                  await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
                  marks.painted = Math.round(performance.now() - t0);
                  done(marks);
                }})();""")
            if run:
                times.append(ms["painted"])
                print(f"run {run}: {ms['painted']} ms (ms after the pick when each answer arrived, the RPs drawn, the image painted: {ms})")
        print(f"median first paint of the floor (pick → 1000 RPs drawn, 3000 px image decoded): {statistics.median(times):.0f} ms")
    finally:
        if driver:
            driver.quit()
        server.close()


if __name__ == "__main__":
    main()
