// Live positions: every device tracked on the shown floor, from the map's positions stream
// (GET /v1/maps/{id}/positions/events?floor_id=, Server-Sent Events). It is read with fetch and
// a ReadableStream, not EventSource, because the stream wants the API key's Authorization
// header, which EventSource cannot send. Each device is a dot with its label, the circle of its
// accuracy_m and the trail of the positions seen since this floor was shown (the stream gives
// latest fixes only; older fixes need the track's own token); its label says where it is in
// words, as the fix does (docs/api.md: the room, and the nearest POI within the checkpoint
// radius). A `leave` event (the device went to another floor, or its track ended) removes it
// here; the other floor's stream shows it there.
import { apiKey } from './api.js';
import { ll } from './image_layer.js';
import { esc } from './floor_view.js';

const L = window.L;

// "phone 7 · Reception · near Info desk": the device, its room and its nearest checkpoint.
export function caption(name, fix) {
  const parts = [name];
  if (fix.room) parts.push(fix.room.name);
  if (fix.nearby && fix.nearby.length) parts.push(`near ${fix.nearby[0].name}`);
  return parts.join(' · ');
}
const TRAIL = 50;             // points of trail kept per device
const RETRY_MS = 2000;        // after a dropped stream (server restart, network)

// The viewer calls this on every floor change, and the returned stop function before the next.
// `note(text)` says why nothing is shown when the server refuses the stream ('' once it is open).
export function followFloor({ mapId, floorId, layer, note = () => {} }) {
  const devices = new Map();  // track id → { trail, line, circle, dot, fix }
  const abort = new AbortController();
  let stopped = false;
  layer.clearLayers();
  layer.locusDevices = devices;  // for tests: read only

  function remove(id) {
    const d = devices.get(id);
    if (!d) return;
    for (const l of [d.line, d.circle, d.dot]) layer.removeLayer(l);
    devices.delete(id);
  }

  function place({ track_id: id, label, fix }) {
    if (fix.floor_id !== floorId) return remove(id);
    const at = ll(fix.x, fix.y);
    let d = devices.get(id);
    const name = label || `track ${id}`;
    if (!d) {
      d = {
        trail: [],
        line: L.polyline([], { className: 'live-trail', interactive: false }),
        circle: L.circle(at, { radius: fix.accuracy_m, className: 'live-accuracy', interactive: false }),
        dot: L.circleMarker(at, { radius: 6, className: 'live-dot' }).bindTooltip(esc(name), { direction: 'top', offset: [0, -6], className: 'label live' }),
      };
      for (const l of [d.line, d.circle, d.dot]) layer.addLayer(l);
      devices.set(id, d);
    }
    d.fix = fix;
    d.trail.push(at);
    if (d.trail.length > TRAIL) d.trail.shift();
    d.line.setLatLngs(d.trail);
    // L.CRS.Simple measures in map units, which are metres here: the radius is accuracy_m.
    d.circle.setLatLng(at).setRadius(fix.accuracy_m);
    d.dot.setLatLng(at).setTooltipContent(esc(caption(name, fix)));
  }

  function handle(block) {
    let name = 'message';
    let data = '';
    for (const line of block.split('\n')) {
      if (line.startsWith('event: ')) name = line.slice(7);
      else if (line.startsWith('data: ')) data += line.slice(6);
    }
    if (!data) return;  // a heartbeat comment
    const ev = JSON.parse(data);
    if (name === 'position') place(ev);
    else if (name === 'leave') remove(ev.track_id);
  }

  async function run() {
    while (!stopped) {
      try {
        const headers = { Accept: 'text/event-stream' };
        const key = apiKey();
        if (key) headers.Authorization = `Bearer ${key}`;
        const res = await fetch(`/v1/maps/${mapId}/positions/events?floor_id=${floorId}`, { headers, signal: abort.signal });
        // No key (or a wrong one), a map gone: nothing to show, and asking again will not change it.
        if (!res.ok) {
          const said = await res.json().then((b) => b.error?.message ?? '', () => '');
          note(res.status === 401 || res.status === 403
            ? 'Live positions are the operator\'s: give the server\'s API key (below) to see them.'
            : `No live positions: ${said || `HTTP ${res.status}`}`);
          return;
        }
        note('');
        // The stream starts with every device's position: what was drawn before is stale.
        for (const id of [...devices.keys()]) remove(id);
        const reader = res.body.pipeThrough(new TextDecoderStream()).getReader();
        let buf = '';
        for (;;) {
          const { value, done } = await reader.read();
          if (done) break;
          buf += value;
          for (let end; (end = buf.indexOf('\n\n')) >= 0; buf = buf.slice(end + 2)) handle(buf.slice(0, end));
        }
      } catch (e) {
        if (stopped) return;  // aborted by stop()
      }
      await new Promise((resolve) => setTimeout(resolve, RETRY_MS));
    }
  }
  run();

  return () => {
    stopped = true;
    abort.abort();
    layer.clearLayers();
  };
}
