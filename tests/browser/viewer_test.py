#!/usr/bin/env python3
"""The web viewer in a real headless Chromium (Debian's chromium + chromium-driver, driven by
python3-selenium) against a real locus-server on 127.0.0.1 with a fresh SQLite database and the
demo map. Asserts what a user sees: the floor picker lists the building's floors, the RP layer
has a marker per RP the API lists, an RP's click shows its APs as the API has them, a heat map
puts colour where RPs are (a screenshot pixel check), gaps are shaded, a searched route is drawn
as long as the API's route and across floors, keyboard users reach the pickers and RPs, a phone
screen needs no sideways scrolling, a tracked phone's dot appears within a second of its fix with
its accuracy circle and follows it to another floor, and the browser logged no error.

    viewer_test.py --server build/bin/locus-server

Chromium missing fails the test (scripts/setup.sh installs it with the developer tools);
LOCUS_SKIP_BROWSER_TEST=1 turns that into a skip (exit 77) on a machine without it.
"""
import argparse
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import urllib.request
import zlib

SKIP = 77
SHOTS = None  # --screenshots: where to save the main views
CLI = None    # --cli: the locus tool, to compare the survey grid with `locus survey plan`


def shot(driver, name):
    if SHOTS:
        driver.save_screenshot(os.path.join(SHOTS, name))


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def check(cond, message):
    if not cond:
        fail(message)
    print(f"ok: {message}")


# ---- the server ---------------------------------------------------------------------------

class Server:
    def __init__(self, binary, extra=()):
        self.dir = tempfile.mkdtemp(prefix="locus-viewer-")
        self.log = open(os.path.join(self.dir, "server.log"), "w+")
        self.proc = subprocess.Popen([binary, "--db", os.path.join(self.dir, "locus.db"), "--port", "0", "--demo", "--quiet", *extra],
                                     stdout=subprocess.DEVNULL, stderr=self.log)
        deadline = time.time() + 15
        self.port = None
        while time.time() < deadline and self.port is None:
            self.log.seek(0)
            for line in self.log:
                try:
                    event = json.loads(line)
                except ValueError:
                    continue
                if event.get("event") == "listening":
                    self.port = event["port"]
                if event.get("event") == "error":
                    fail(f"server: {event}")
            time.sleep(0.05)
        if self.port is None:
            fail("the server did not start")
        self.url = f"http://127.0.0.1:{self.port}"

    def api(self, path, body=None, method=None, content_type="application/json", headers=None):
        data = body if isinstance(body, bytes) or body is None else json.dumps(body).encode()
        req = urllib.request.Request(self.url + path, data=data, method=method or ("GET" if body is None else "POST"),
                                     headers={"Content-Type": content_type, **(headers or {})})
        with urllib.request.urlopen(req, timeout=10) as r:
            return json.loads(r.read())

    def close(self):
        self.proc.terminate()
        self.proc.wait(timeout=10)
        self.log.close()
        shutil.rmtree(self.dir, ignore_errors=True)


# ---- a PNG screenshot's pixels (no imaging library needed) --------------------------------

def decode_png(data):
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        chunk = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", chunk)
            assert depth == 8 and colour in (2, 6) and interlace == 0, "unexpected PNG format"
            bpp = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += chunk
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return lambda x, y: tuple(rows[y][x * bpp:x * bpp + 3])


# ---- the browser --------------------------------------------------------------------------

def start_browser(width, height):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    options = webdriver.ChromeOptions()
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                f"--window-size={width},{height}", "--force-device-scale-factor=1", "--no-first-run",
                "--disable-background-networking", "--disable-component-update"):
        options.add_argument(arg)
    options.binary_location = shutil.which("chromium")
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)


def wait(driver, script, what, timeout=10):
    deadline = time.time() + timeout
    while time.time() < deadline:
        value = driver.execute_script(script)
        if value:
            return value
        time.sleep(0.05)
    fail(f"timed out waiting for {what}")


def wait_floor(driver, floor_id):
    wait(driver, f"return document.body.dataset.floorReady === 'true' && window.locusViewer.state.floor.id === {floor_id}",
         f"floor {floor_id} drawn")


def screen_point(driver, x, y):
    return driver.execute_script(
        "const m = window.locusViewer.map; const p = m.latLngToContainerPoint(L.latLng(arguments[1], arguments[0]));"
        "const r = m.getContainer().getBoundingClientRect(); return [Math.round(r.left + p.x), Math.round(r.top + p.y)];", x, y)


def errors_in_log(driver, expected=()):
    bad = []
    for entry in driver.get_log("browser"):
        if entry["level"] != "SEVERE":
            continue
        # A floor without a plan image answers 404 to its placement: the viewer asks, as the
        # API has no other way to tell, and Chromium logs every 4xx it fetched.
        if "/image/placement - Failed to load resource: the server responded with a status of 404" in entry["message"]:
            continue
        if any(e in entry["message"] for e in expected):
            continue
        bad.append(entry["message"])
    return bad


def desktop_checks(driver, server):
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import Select
    from selenium.webdriver.common.action_chains import ActionChains

    buildings = server.api("/v1/maps/1/buildings")["items"]
    floors = sorted(server.api(f"/v1/buildings/{buildings[0]['id']}/floors")["items"], key=lambda f: f["level"])
    ground = next(f for f in floors if f["level"] == 0)
    driver.get(server.url + "/")
    wait_floor(driver, ground["id"])

    # The floor picker lists the building's floors.
    options = [o.text for o in Select(driver.find_element(By.ID, "floor-select")).options]
    check(options == [f"{f['name']} (level {f['level']})" for f in floors], f"floor picker lists {options}")

    # One marker per RP the API lists.
    radiomap = server.api(f"/v1/floors/{ground['id']}/radiomaps")["items"][0]
    rps = server.api(f"/v1/radiomaps/{radiomap['id']}/rps?limit=1000")
    markers = driver.find_elements(By.CSS_SELECTOR, "#map .rp-marker")
    check(len(markers) == rps["total"] > 0, f"{len(markers)} RP markers for {rps['total']} RPs")

    # Clicking an RP shows its APs, as stored.
    rp = rps["items"][0]
    driver.find_element(By.CSS_SELECTOR, f".rp-marker[title='RP {rp['name']}']").click()
    wait(driver, "return document.querySelectorAll('#rp-table tbody tr').length > 0", "the RP's AP table")
    stored = server.api(f"/v1/rps/{rp['id']}")
    shown = [tr.find_element(By.TAG_NAME, "th").text for tr in driver.find_elements(By.CSS_SELECTOR, "#rp-table tbody tr")]
    check(sorted(shown) == sorted(m["bssid"] for m in stored["measurements"]), f"RP {rp['name']} shows its {len(shown)} APs")
    strongest = max(stored["measurements"], key=lambda m: m["mean"])
    first_row = driver.find_elements(By.CSS_SELECTOR, "#rp-table tbody tr")[0].text
    check(strongest["bssid"] in first_row and f"{strongest['mean']:.1f}" in first_row and str(strongest["count"]) in first_row,
          f"the strongest AP first with its mean and count: {first_row}")
    # Its last upload: the demo's RPs were imported, so none; after one, the stored time in local time.
    check(driver.find_element(By.ID, "rp-last-upload").text == "never" and stored["last_upload_at"] is None,
          "an imported RP's last upload is 'never'")
    server.api(f"/v1/rps/{rp['id']}/scans", {"scans": [[{"bssid": strongest["bssid"], "rss": -50}]]})
    at = server.api(f"/v1/rps/{rp['id']}")["last_upload_at"]
    driver.find_element(By.CSS_SELECTOR, f".rp-marker[title='RP {rp['name']}']").click()
    wait(driver, f"const t = document.getElementById('rp-last-upload'); return t && t.getAttribute('datetime') === {json.dumps(at)}",
         "the RP's last upload after a scan upload")
    local = driver.execute_script(f"return new Date({json.dumps(at)}).toLocaleString()")
    check(at is not None and driver.find_element(By.ID, "rp-last-upload").text == local,
          f"the last upload shown in local time: {local}")

    # The heat map of an AP colours the floor around the RPs that heard it.
    between = ((rps["items"][0]["x"] + rps["items"][1]["x"]) / 2, rps["items"][0]["y"] + 1.0)
    px, py = screen_point(driver, *between)
    before = decode_png(driver.get_screenshot_as_png())(px, py)
    Select(driver.find_element(By.ID, "ap-select")).select_by_value(strongest["bssid"])
    wait(driver, "const i = document.querySelector('img.heat-layer'); return i && i.complete && i.naturalWidth > 0", "the heat map")
    wait(driver, "return document.querySelector('.legend') !== null", "the legend")
    time.sleep(0.2)
    after = decode_png(driver.get_screenshot_as_png())(px, py)
    check(after != before and max(after) - min(after) > 25, f"heat map pixel at {between} m: {before} -> {after}")
    legend = driver.find_element(By.CSS_SELECTOR, ".legend").text
    check("dBm" in legend, f"legend in dBm: {legend!r}")
    shot(driver, "viewer-heatmap.png")

    # Gaps: with a 1 m reach most of the floor is far from any RP.
    gap = driver.find_element(By.ID, "gap-metres")
    gap.clear()
    gap.send_keys("1")
    driver.find_element(By.ID, "gaps-toggle").click()
    wait(driver, "return document.querySelector('img.gaps-layer') !== null", "the gaps layer")
    summary = driver.find_element(By.ID, "radio-summary").text
    check("farther than 1 m" in summary, f"gap summary: {summary!r}")

    # Search, pick both ends, route: the drawn line is as long as the API's route.
    def pick(query, end):
        box = driver.find_element(By.ID, "search-input")
        box.clear()
        box.send_keys(query, Keys.ENTER)
        wait(driver, f"return document.querySelector('#search-results .hit-{end}') !== null", f"search hits for {query}")
        driver.find_element(By.CSS_SELECTOR, f"#search-results .hit-{end}").click()
    pick("main exit", "from")
    pick("lab", "to")
    driver.find_element(By.ID, "route-go").click()
    wait(driver, "return document.getElementById('route-length') !== null", "the route")
    api_route = server.api("/v1/maps/1/route", {"from": {"poi_id": server.api("/v1/maps/1/search?q=main%20exit")["hits"][0]["id"]},
                                               "to": {"room_id": server.api("/v1/maps/1/search?q=lab")["hits"][0]["id"]}})
    drawn = driver.execute_script(
        "let s = 0; for (const l of window.locusViewer.route.polylines) { const p = l.getLatLngs();"
        " for (let i = 1; i < p.length; ++i) s += Math.hypot(p[i].lat - p[i-1].lat, p[i].lng - p[i-1].lng); } return s;")
    shown_length = float(driver.find_element(By.ID, "route-length").get_attribute("data-length-m"))
    check(abs(drawn - api_route["length_m"]) < 1e-6 and abs(shown_length - api_route["length_m"]) < 1e-6,
          f"route drawn {drawn:.3f} m, API {api_route['length_m']:.3f} m")
    check(len(driver.find_elements(By.CSS_SELECTOR, "#map path.route-line")) == 1, "one route line on the map")
    # The time as `locus route` prints it (tools/commands/route.cpp): seconds under 90 s, else minutes.
    t = api_route["time_s"]
    said = f"about {round(t)} s" if t < 90 else f"about {t / 60:.1f} min"
    summary = driver.find_element(By.ID, "route-length").text
    check(said in summary, f"the route's time as the CLI says it ({said}): {summary}")
    steps = [li.text for li in driver.find_elements(By.CSS_SELECTOR, "#route-steps li.step")]
    check(steps == [s["text"] for s in api_route["steps"]], f"instructions as the API's: {steps}")
    shot(driver, "viewer-route.png")

    # A route to the other floor: one leg drawn per floor, the leg button moves between them.
    upper = next(f for f in floors if f["level"] == 1)
    upper_rooms = server.api(f"/v1/floors/{upper['id']}/rooms")["items"]
    pick(upper_rooms[0]["name"], "to")
    driver.find_element(By.ID, "route-go").click()
    wait(driver, "return document.querySelectorAll('#route-steps .leg-floor').length === 2", "a two-floor route")
    driver.find_elements(By.CSS_SELECTOR, "#route-steps .leg-floor")[1].click()
    wait_floor(driver, upper["id"])
    on_upper = driver.execute_script("return window.locusViewer.route.polylines.length")
    check(on_upper == 1 and len(driver.find_elements(By.CSS_SELECTOR, "#map path.route-line")) == 1,
          "the upper floor's leg drawn after its button")

    # Keyboard: Tab reaches the floor picker; arrows change the floor; an RP takes focus and Enter.
    keys = lambda key: ActionChains(driver).send_keys(key).perform()  # to whatever has the focus, as a user types
    driver.get(server.url + "/")  # a fresh page: the first Tab starts at its top
    wait_floor(driver, ground["id"])
    seen = []
    for _ in range(10):
        keys(Keys.TAB)
        seen.append(driver.execute_script("return document.activeElement.id || document.activeElement.tagName"))
        if seen[-1] == "floor-select":
            break
    check(driver.execute_script("return document.activeElement.id") == "floor-select", f"Tab reaches the floor picker: {seen}")
    keys(Keys.ARROW_DOWN)
    wait_floor(driver, upper["id"])
    check(True, "the arrow key chose the upper floor")
    for _ in range(60):
        if driver.execute_script("return document.activeElement.classList.contains('rp-marker')"):
            break
        keys(Keys.TAB)
    check(driver.execute_script("return document.activeElement.classList.contains('rp-marker')"), "Tab reaches an RP marker")
    focused = driver.execute_script("return document.activeElement.title")
    keys(Keys.ENTER)
    wait(driver, f"return document.querySelector('#rp-details strong') && 'RP ' + document.querySelector('#rp-details strong').textContent === {json.dumps(focused)}",
         "Enter on the focused RP shows it")
    check(True, f"Enter on {focused} shows its table")

    # The survey planner: its grid is `locus survey plan`'s, a click adds a point, and "Create
    # RPs" puts them in the radio map (this server has no key).
    if CLI:
        driver.find_element(By.ID, "survey-mode").click()
        cell = driver.find_element(By.ID, "grid-cell")
        cell.clear()
        cell.send_keys("2.5")
        driver.find_element(By.ID, "grid-fill").click()
        mine = driver.execute_script("return window.locusViewer.survey.planDocument()")
        out = subprocess.run([CLI, "survey", "plan", "--server", server.url, "--floor", str(upper["id"]), "--cell", "2.5"],
                             capture_output=True, text=True, timeout=30)
        theirs = json.loads(out.stdout)
        same = [(p["name"], round(p["x"], 6), round(p["y"], 6)) for p in mine["points"]] == \
               [(p["name"], round(p["x"], 6), round(p["y"], 6)) for p in theirs["points"]]
        check(same and all(mine[k] == theirs[k] for k in ("floor_id", "cell", "required_points", "columns", "rows", "proposed")),
              f"the viewer's grid is the CLI's: {mine['proposed']} points of {theirs['required_points']}")
        before = len(mine["points"])
        px, py = screen_point(driver, 1.0, 1.0)
        map_el = driver.find_element(By.ID, "map")
        r = driver.execute_script("const r = arguments[0].getBoundingClientRect(); return [r.left + r.width / 2, r.top + r.height / 2];", map_el)
        ActionChains(driver).move_to_element_with_offset(map_el, int(px - r[0]), int(py - r[1])).click().perform()
        check(driver.execute_script("return window.locusViewer.survey.points.length") == before + 1, "a map click adds a planned RP")
        rm_upper = server.api(f"/v1/floors/{upper['id']}/radiomaps")["items"][0]["id"]
        total_before = server.api(f"/v1/radiomaps/{rm_upper}/rps?limit=1")["total"]
        driver.find_element(By.ID, "survey-create").click()
        wait(driver, "return document.getElementById('status').textContent.startsWith('Created')", "the planned RPs created")
        total_after = server.api(f"/v1/radiomaps/{rm_upper}/rps?limit=1")["total"]
        check(total_after == total_before + before + 1, f"radio map has {total_after} RPs, {before + 1} more")
        wait(driver, f"return document.querySelectorAll('#map .rp-marker').length === {total_after}", "the new RPs drawn")
        driver.find_element(By.ID, "survey-mode").click()

    # A turned plan image lies where its placement's corners say.
    server.api(f"/v1/floors/{ground['id']}/image?metres_per_pixel=0.05", grey_png(600, 300), "PUT", "image/png")
    corners = server.api(f"/v1/floors/{ground['id']}/image/placement", {"rotation_deg": 15, "origin_x": 2}, "PATCH")["corners"]
    driver.get(server.url + "/")
    wait_floor(driver, ground["id"])
    wait(driver, "const i = document.querySelector('img.plan-image.rotated'); return i && i.complete && i.naturalWidth > 0", "the turned plan image")
    box = driver.execute_script("const r = document.querySelector('img.plan-image.rotated').getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom];")
    pts = [screen_point(driver, x, y) for x, y in corners]
    want = [min(p[0] for p in pts), min(p[1] for p in pts), max(p[0] for p in pts), max(p[1] for p in pts)]
    check(all(abs(a - b) <= 2 for a, b in zip(box, want)), f"turned image spans {[round(v) for v in box]}, its corners {want}")

    errors = errors_in_log(driver)
    check(not errors, f"no console errors {errors}")


def link_checks(driver, server):
    """The address names the map and floor shown: a link to the upper floor opens it, choosing
    another floor changes the address, and a link pasted into the open page is followed."""
    from selenium.webdriver.support.ui import Select
    from selenium.webdriver.common.by import By

    buildings = server.api("/v1/maps/1/buildings")["items"]
    floors = sorted(server.api(f"/v1/buildings/{buildings[0]['id']}/floors")["items"], key=lambda f: f["level"])
    ground = next(f for f in floors if f["level"] == 0)
    upper = next(f for f in floors if f["id"] != ground["id"])
    driver.get(f"{server.url}/#map=1&floor={upper['id']}")
    wait_floor(driver, upper["id"])
    check(True, "a link to the upper floor opened it")
    Select(driver.find_element(By.ID, "floor-select")).select_by_value(str(ground["id"]))
    wait_floor(driver, ground["id"])
    wait(driver, f"return location.hash === '#map=1&floor={ground['id']}'", "the address naming the floor chosen")
    driver.execute_script(f"location.hash = '#map=1&floor={upper['id']}'")
    wait_floor(driver, upper["id"])
    check(True, "a link pasted into the open page is followed")
    driver.get("about:blank")  # a new load, not a hash change of the open page
    driver.get(f"{server.url}/#map=999&floor=abc")
    wait_floor(driver, ground["id"])
    check(True, "a link naming no map of the server opens the first map's ground floor")


def live_checks(driver, server):
    """A phone's track: its dot appears on the shown floor within a second of its fix, with the
    accuracy circle's radius and a label saying where it is in words (its room and nearest
    checkpoint, as the fix says), moves with its trail, and follows it to another floor."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import Select

    buildings = server.api("/v1/maps/1/buildings")["items"]
    floors = sorted(server.api(f"/v1/buildings/{buildings[0]['id']}/floors")["items"], key=lambda f: f["level"])
    ground = next(f for f in floors if f["level"] == 0)
    upper = next(f for f in floors if f["id"] != ground["id"])
    driver.get(server.url + "/")
    wait_floor(driver, ground["id"])
    track = server.api("/v1/tracks", {"map_id": 1, "label": "phone 7"}, "POST")
    token = {"X-Track-Token": track["token"]}
    devices = "return window.locusViewer.liveLayer.locusDevices !== undefined;"
    device = ("const d = window.locusViewer.liveLayer.locusDevices; const v = d && d.get(arguments[0]);"
              "return v ? {x: v.fix.x, y: v.fix.y, floor: v.fix.floor_id, r: v.circle.getRadius(), trail: v.trail.length,"
              " tip: v.dot.getTooltip().getContent(),"
              " circle: v.circle.getElement().getBoundingClientRect().width, dot: v.dot.getElement().getBoundingClientRect()} : null;")

    def fix_at(floor, x, y, accuracy):
        nonlocal posted
        posted = time.time()  # the phone's send: the dot's delay counts the POST too
        return server.api(f"/v1/tracks/{track['id']}/fixes",
                          {"fixes": [{"t": time.time(), "floor_id": floor, "x": x, "y": y, "accuracy_m": accuracy}]}, "POST", headers=token)

    posted = time.time()

    def wait_device(script_test, what, within=1.0):
        deadline = time.time() + within + 2  # judged below, so a slow frame reports a figure rather than a timeout
        while time.time() < deadline:
            v = driver.execute_script(device, track["id"])
            if script_test(v):
                return v, time.time() - posted
            time.sleep(0.02)
        fail(f"timed out waiting for {what}")

    wait(driver, devices, "the live layer following the floor")
    # A checkpoint half a metre from where the phone will be: its label names it.
    server.api(f"/v1/floors/{ground['id']}/pois", {"name": "Info point", "kind": "desk", "x": 6.5, "y": 4.0}, "POST")
    answer = fix_at(ground["id"], 6.0, 4.0, 2.5)
    v, took = wait_device(lambda v: v is not None, "the phone's dot")
    room = answer["latest"]["room"]
    want_tip = "phone 7" + (f" · {room['name']}" if room else "") + " · near Info point"
    check(v["tip"] == want_tip, f"the dot's label says where it is: {v['tip']!r}, the fix says {want_tip!r}")
    check(took < 1.0, f"the phone's dot appeared {took:.2f} s after its fix")
    check(abs(v["x"] - 6.0) < 1e-9 and v["floor"] == ground["id"] and v["r"] == 2.5, f"at its fix with the accuracy radius: {v}")
    px0 = screen_point(driver, 6.0, 4.0)
    px1 = screen_point(driver, 8.5, 4.0)
    want = 2 * (px1[0] - px0[0])
    check(abs(v["circle"] - want) <= 2, f"the accuracy circle is {v['circle']:.0f} px wide, 2 × 2.5 m = {want} px")
    centre = (v["dot"]["left"] + v["dot"]["width"] / 2, v["dot"]["top"] + v["dot"]["height"] / 2)
    check(abs(centre[0] - px0[0]) <= 2 and abs(centre[1] - px0[1]) <= 2, f"the dot drawn at {centre}, its fix at {px0}")

    fix_at(ground["id"], 10.0, 5.0, 1.0)
    v, took = wait_device(lambda v: v is not None and v["x"] == 10.0, "the dot to move")
    check(took < 1.0 and v["trail"] == 2 and v["r"] == 1.0, f"moved in {took:.2f} s, trail of {v['trail']}, radius {v['r']}")

    fix_at(upper["id"], 3.0, 3.0, 1.5)
    v, took = wait_device(lambda v: v is None, "the dot to leave the ground floor")
    check(took < 1.0, f"the phone left the ground floor's view {took:.2f} s after a fix upstairs")
    Select(driver.find_element(By.ID, "floor-select")).select_by_value(str(upper["id"]))
    wait_floor(driver, upper["id"])
    v, took = wait_device(lambda v: v is not None, "the dot upstairs")
    check(v["floor"] == upper["id"] and v["x"] == 3.0 and v["r"] == 1.5, f"shown upstairs: {v}")
    check(len(driver.find_elements(By.CSS_SELECTOR, "#map .live-dot")) == 1, "one live dot drawn")
    shot(driver, "viewer-live.png")
    server.api(f"/v1/tracks/{track['id']}/close", {}, "POST", headers=token)
    wait_device(lambda v: v is None, "the closed track's dot to go")
    errors = errors_in_log(driver)
    check(not errors, f"no console errors with live positions {errors}")


def quality_checks(driver, server):
    """The predicted-error layer: one coloured dot per RP the quality endpoint localized on the
    floor, the worst the reddest, a legend up to the worst error (at least 10 m)."""
    from selenium.webdriver.common.by import By
    driver.get(server.url + "/")
    wait(driver, "return document.body.dataset.floorReady === 'true'", "the floor")
    floor = driver.execute_script("return window.locusViewer.state.floor.id")
    rm = driver.execute_script("return window.locusViewer.state.radiomapId")
    q = server.api(f"/v1/radiomaps/{rm}/quality")
    here = [r for r in q["rps"] if r["floor_id"] == floor and r["error_m"] is not None]
    driver.find_element(By.ID, "quality-toggle").click()
    wait(driver, "return document.querySelector('.quality-legend') !== null", "the predicted-error legend")
    dots = driver.find_elements(By.CSS_SELECTOR, "#map .quality-rp")
    check(len(dots) == len(here) > 0, f"{len(dots)} predicted-error dots for {len(here)} RPs localized on the floor")
    shown = driver.execute_script("return window.locusViewer.quality.shown")
    worst = max(shown, key=lambda r: r["error_m"])
    best = min(shown, key=lambda r: r["error_m"])
    check(abs(worst["error_m"] - max(r["error_m"] for r in here)) < 1e-9, f"the worst RP {worst['name']} at {worst['error_m']:.1f} m, as the API says")
    red = lambda c: [int(v) for v in c[4:-1].split(",")]
    check(worst["error_m"] == best["error_m"] or red(worst["colour"])[0] - red(worst["colour"])[1] > red(best["colour"])[0] - red(best["colour"])[1],
          f"the worst RP redder ({worst['colour']}) than the best ({best['colour']})")
    legend = driver.find_element(By.CSS_SELECTOR, ".quality-legend").text
    top = max(10, worst["error_m"])
    check(legend.strip().endswith(f"{top:.0f}"), f"legend up to {top:.0f} m: {legend!r}")
    driver.find_element(By.ID, "quality-toggle").click()
    wait(driver, "return document.querySelectorAll('#map .quality-rp').length === 0 && !document.querySelector('.quality-legend')", "the layer off")
    errors = errors_in_log(driver)
    check(not errors, f"no console errors with the predicted-error layer {errors}")


def grey_png(width, height):
    row = b"\x00" + b"\x80" * width

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(row * height)) + chunk(b"IEND", b""))


def key_checks(driver, server):
    """A server with an API key: the viewer reads without it; creating RPs asks for it."""
    from selenium.webdriver.common.by import By
    driver.get(server.url + "/")
    wait(driver, "return document.body.dataset.floorReady === 'true' && document.querySelectorAll('#map .rp-marker').length > 0",
         "the floor drawn without a key")
    floor = driver.execute_script("return window.locusViewer.state.floor.id")
    rm = server.api(f"/v1/floors/{floor}/radiomaps")["items"][0]["id"]
    total = server.api(f"/v1/radiomaps/{rm}/rps?limit=1")["total"]
    driver.find_element(By.ID, "survey-mode").click()
    driver.find_element(By.ID, "grid-fill").click()
    planned = driver.execute_script("return window.locusViewer.survey.points.length")
    driver.find_element(By.ID, "survey-create").click()
    wait(driver, "return document.getElementById('live-status').textContent.includes('API key')",
         "the live layer saying why it shows nothing")
    wait(driver, "return document.activeElement.id === 'api-key'", "the key asked for")
    check("API key" in driver.find_element(By.ID, "status").text and server.api(f"/v1/radiomaps/{rm}/rps?limit=1")["total"] == total,
          "without the key nothing is created and the key field takes the focus")
    driver.find_element(By.ID, "api-key").send_keys("viewer-test-key")
    driver.find_element(By.ID, "api-key-save").click()
    driver.find_element(By.ID, "survey-create").click()
    wait(driver, "return document.getElementById('status').textContent.startsWith('Created')", "the RPs created with the key")
    check(server.api(f"/v1/radiomaps/{rm}/rps?limit=1")["total"] == total + planned, f"with the key, {planned} RPs created")
    check(driver.execute_script("return localStorage.getItem('locus.apiKey')") == "viewer-test-key", "the key kept in this browser")
    # The live layer asked for positions, which need the key, before it was given, and said so;
    # with the key saved it follows the floor again, and the note goes.
    wait(driver, "return document.getElementById('live-status').textContent === ''", "the live note gone with the key")
    # The live layer asks for positions, which need the key, before it is given.
    errors = errors_in_log(driver, expected=["/rps - Failed to load resource: the server responded with a status of 401",
                                             "/positions/events?floor_id="])
    check(not errors, f"no console errors but the refused write {errors}")


def create_checks(driver, server):
    """A map, a building and a floor of one's own, made in the viewer and shown at once."""
    from selenium.webdriver.common.by import By
    driver.get(server.url + "/")
    wait(driver, "return document.body.dataset.floorReady === 'true'", "the viewer loaded")
    maps_before = server.api("/v1/maps")["total"]
    def submit(form, values):
        for field, value in values.items():
            el = driver.find_element(By.ID, field)
            el.clear()
            el.send_keys(value)
        driver.find_element(By.CSS_SELECTOR, f"#{form} button[type=submit]").click()
    submit("new-map", {"new-map-name": "Viewer-made map"})
    wait(driver, "const s = document.getElementById('map-select'); return s.options[s.selectedIndex]?.text === 'Viewer-made map'",
         "the new map chosen")
    check(server.api("/v1/maps")["total"] == maps_before + 1, "the map created on the server")
    submit("new-building", {"new-building-name": "Annex"})
    wait(driver, "const s = document.getElementById('building-select'); return s.options[s.selectedIndex]?.text === 'Annex'",
         "the new building chosen")
    submit("new-floor", {"new-floor-name": "Ground", "new-floor-level": "0", "new-floor-width": "12.3456789",
                         "new-floor-height": "8"})
    wait(driver, "const s = document.getElementById('floor-select'); return s.options[s.selectedIndex]?.text === 'Ground (level 0)'"
         " && document.body.dataset.floorReady === 'true'", "the new floor drawn")
    status = driver.find_element(By.ID, "status").text
    check("12.35 m × 8 m" in status, f"the floor's size rounded for people: {status!r}")
    map_id = driver.execute_script("return window.locusViewer.state.mapId")
    buildings = server.api(f"/v1/maps/{map_id}/buildings")["items"]
    check([b["name"] for b in buildings] == ["Annex"], f"the building created in the new map: {buildings}")
    floors = server.api(f"/v1/buildings/{buildings[0]['id']}/floors")["items"]
    check(len(floors) == 1 and floors[0]["width"] == 12.3456789, f"the floor created as typed: {floors}")
    # A refused create says why and changes nothing.
    submit("new-map", {"new-map-name": "Viewer-made map"})
    wait(driver, "return document.getElementById('status').textContent.startsWith('Error:')", "the duplicate refused")
    check(server.api("/v1/maps")["total"] == maps_before + 1, "a refused create writes nothing")
    # A floor without a plan answers 404 to it, as a floor without an image does to its placement.
    errors = errors_in_log(driver, expected=["/v1/maps - Failed to load resource: the server responded with a status of 409",
                                             "/plan - Failed to load resource: the server responded with a status of 404"])
    check(not errors, f"no console errors but the refused duplicate {errors}")


def phone_checks(driver, server):
    from selenium.webdriver.common.by import By
    # A phone's screen, as DevTools' device mode sets it (a headless window is at least 500 px wide).
    driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", {"width": 390, "height": 844, "deviceScaleFactor": 1, "mobile": True})
    driver.get(server.url + "/")
    wait(driver, "return document.body.dataset.floorReady === 'true'", "the floor on a phone")
    sizes = driver.execute_script(
        "const m = document.getElementById('map').getBoundingClientRect(); const f = document.getElementById('floor-select').getBoundingClientRect();"
        "return {scroll: document.documentElement.scrollWidth, inner: document.documentElement.clientWidth, mapW: m.width, mapH: m.height, floorRight: f.right};")
    check(sizes["scroll"] <= sizes["inner"], f"no sideways scrolling on a phone: {sizes}")
    check(sizes["inner"] <= 390 and sizes["mapW"] >= sizes["inner"] - 2 and sizes["mapH"] >= 300, "the map spans the phone's width")
    check(sizes["floorRight"] <= sizes["inner"], "the floor picker is on screen")
    check(len(driver.find_elements(By.CSS_SELECTOR, "#map .rp-marker")) > 0, "RPs drawn on a phone")
    shot(driver, "viewer-phone.png")
    errors = errors_in_log(driver)
    check(not errors, f"no console errors on a phone {errors}")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--server", required=True, help="the locus-server binary")
    parser.add_argument("--cli", help="the locus tool (checks the survey grid against `locus survey plan`)")
    parser.add_argument("--screenshots", help="save the main views' screenshots into this directory")
    args = parser.parse_args()
    global SHOTS, CLI
    SHOTS = args.screenshots
    CLI = args.cli
    missing = [name for name in ("chromium", "chromedriver") if not shutil.which(name)]
    try:
        import selenium  # noqa: F401
    except ImportError:
        missing.append("python3-selenium")
    if missing:
        message = f"{', '.join(missing)} not installed (scripts/setup.sh with LOCUS_DEVTOOLS=1 installs them)"
        if os.environ.get("LOCUS_SKIP_BROWSER_TEST") == "1":
            print(f"SKIP: {message}")
            return SKIP
        fail(message)

    started = time.time()
    server = Server(args.server)
    driver = None
    try:
        driver = start_browser(1280, 800)
        desktop_checks(driver, server)
        live_checks(driver, server)
        link_checks(driver, server)
        quality_checks(driver, server)
        create_checks(driver, server)
        driver.quit()
        driver = start_browser(390, 844)
        phone_checks(driver, server)
        driver.quit()
        driver = None
        keyed = Server(args.server, ["--api-key", "viewer-test-key"])
        try:
            driver = start_browser(1280, 800)
            key_checks(driver, keyed)
        finally:
            keyed.close()
    finally:
        if driver:
            driver.quit()
        server.close()
    print(f"all viewer checks passed in {time.time() - started:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
