// Traffic for the contract check (scripts/contract_check.sh starts the server and Prism and
// runs this). Every request goes through Prism's validating proxy, which forwards it to the
// real locus-server and reports in the `sl-violations` header where the request or the
// answer departs from schema/openapi.yaml. A violation is any of:
//   - Prism found the answer off the spec (undocumented status, body or header off its schema);
//   - Prism found a request off the spec that was meant to be valid;
//   - a request meant to be invalid (the server refuses it) that the spec accepts: the spec
//     is looser than the server there;
//   - an unexpected status, an answer whose status the operation does not document;
//   - an operation of the spec that got no request, or no successful one;
//   - a request Prism answered itself instead of forwarding it.
// A POST or PATCH without a Content-Length cannot pass through Prism (it adds one), so those
// (411) are sent straight to the server, one per body-taking operation, and their answers
// are checked here against the operation's documented 411 (status, error code, shape).
// Prism does not forward a binary body intact (a plan image's bytes arrive re-encoded), so an
// upload that must succeed goes straight to the server (`direct`), its status checked against
// the operation's; the image's reads and every refused upload still go through Prism.
// Node 18+ (built-in fetch), no dependencies.
//
// Environment: CONTRACT_PROXY (Prism's URL), CONTRACT_SERVER (the server's URL), CONTRACT_SPEC_JSON (the spec bundled as JSON),
// CONTRACT_API_KEY (the server's key), CONTRACT_SERVER_LOG (the server's access log),
// CONTRACT_SKIP (operationIds not to exercise, comma-separated; listed in the summary).
import { readFileSync } from 'node:fs';
import { connect } from 'node:net';

const proxy = process.env.CONTRACT_PROXY;
const server = new URL(process.env.CONTRACT_SERVER);
const apiKey = process.env.CONTRACT_API_KEY;
const spec = JSON.parse(readFileSync(process.env.CONTRACT_SPEC_JSON, 'utf8'));
const serverLog = process.env.CONTRACT_SERVER_LOG;
const skip = new Set((process.env.CONTRACT_SKIP || '').split(',').map((s) => s.trim()).filter(Boolean));

// The spec's operations, each with a regex for its path and the statuses it documents.
const operations = [];
for (const [template, item] of Object.entries(spec.paths)) {
  const regex = new RegExp('^' + template.replace(/\{[^}]+\}/g, '[^/]+') + '$');
  for (const method of ['get', 'put', 'post', 'patch', 'delete', 'head', 'options']) {
    if (!item[method]) continue;
    operations.push({
      id: item[method].operationId || `${method.toUpperCase()} ${template}`,
      method: method.toUpperCase(),
      template,
      regex,
      statuses: Object.keys(item[method].responses || {}),
      responses: item[method].responses || {},
      hasBody: !!item[method].requestBody,
      // An action whose body is optional takes a POST with no length as an empty body.
      bodyOptional: item[method].requestBody?.required === false,
      seen: [],
    });
  }
}
for (const id of skip)
  if (!operations.some((op) => op.id === id)) {
    console.error(`contract: CONTRACT_SKIP names no operation of the spec: ${id}`);
    process.exit(2);
  }

const violations = [];
let sent = 0;
let direct = 0;
let cut = 0;  // open streams cut by the client: the server logs each at its next heartbeat, maybe after this run
let skipped = 0;

function operationOf(method, path) {
  const bare = path.split('?')[0];
  return operations.find((op) => op.method === method && op.regex.test(bare));
}

// Sends one request through Prism and checks it. `invalid`: the request breaks the spec on
// purpose (the server must refuse it, and Prism must flag it). Writes carry the key unless
// `auth` is false; reads and localize carry none unless `auth` is true.
async function call(method, path, { body, raw, contentType, auth, headers = {}, expect, invalid = false, direct: straight = false, stream = false } = {}) {
  const op = operationOf(method, path);
  const what = `${method} ${path}${invalid ? ' (invalid on purpose)' : ''}`;
  if (op && skip.has(op.id)) {
    skipped++;
    return { status: 0, json: null };
  }
  const h = { ...headers };
  const bare = path.split('?')[0];
  const isWrite = method !== 'GET' && !bare.endsWith('/localize') && !bare.endsWith('/route');
  if (auth === true || (auth === undefined && isWrite)) h.authorization = `Bearer ${apiKey}`;
  let payload;
  if (raw !== undefined) payload = raw;
  else if (body !== undefined) payload = JSON.stringify(body);
  if (payload !== undefined) h['content-type'] = contentType || 'application/json';

  if (!straight) sent++;
  let res;
  let text;
  try {
    if (straight) direct++;  // counted here: a failed send still reached for the server
    res = await fetch((straight ? server.origin : proxy) + path, { method, headers: h, body: payload, signal: AbortSignal.timeout(20000) });
    // A stream that stays open (the map's positions) is judged by its status and headers only.
    if (stream && res.ok) {
      cut++;
      await res.body?.cancel();
      text = '';
    } else {
      text = await res.text();
    }
  } catch (e) {
    violations.push(`${what}: no answer (${e.message})`);
    return { status: 0, json: null };
  }
  let json = null;
  try {
    json = text ? JSON.parse(text) : null;
  } catch {
    json = null;
  }

  let found = [];
  const header = res.headers.get('sl-violations');
  if (header) {
    try {
      found = JSON.parse(header);
    } catch {
      found = [{ location: ['response'], message: header.slice(0, 300) }];
    }
  }
  const where = (v) => (v.location || []).join('.');
  for (const v of found) {
    const side = (v.location || [])[0];
    if (side === 'request' && invalid) continue;
    violations.push(`${what} -> ${res.status}: ${v.severity || ''} ${where(v)}: ${v.message}`);
  }
  if (invalid && !found.some((v) => (v.location || [])[0] === 'request'))
    violations.push(`${what} -> ${res.status}: the spec accepts this request, the server refuses it`);
  if (expect !== undefined && res.status !== expect)
    violations.push(`${what}: expected ${expect}, got ${res.status} ${text.slice(0, 200)}`);
  if (!op) violations.push(`${what}: no operation of the spec matches`);
  else {
    op.seen.push(res.status);
    if (!op.statuses.includes(String(res.status)))
      violations.push(`${what} -> ${res.status}: ${op.id} does not document status ${res.status}`);
  }
  if ((res.headers.get('content-type') || '').includes('problem+json'))
    violations.push(`${what} -> ${res.status}: Prism answered itself: ${text.slice(0, 200)}`);
  return { status: res.status, json, headers: res.headers };
}

const post = (path, body, opts = {}) => call('POST', path, { body, ...opts });
const patch = (path, body, opts = {}) => call('PATCH', path, { body, ...opts });
const get = (path, opts = {}) => call('GET', path, opts);
const del = (path, opts = {}) => call('DELETE', path, opts);
const put = (path, body, opts = {}) => call('PUT', path, { body, ...opts });
const idOf = (r, what) => {
  if (!r.json || typeof r.json.id !== 'number') throw new Error(`contract: could not create ${what}; stopping`);
  return r.json.id;
};

const UNKNOWN = 999999;
const ap = (n) => `00:1a:2b:00:00:${String(n).padStart(2, '0')}`;
const scan = (...pairs) => pairs.map(([n, rss]) => ({ bssid: ap(n), rss }));

async function run() {
  // Probes
  await get('/health', { expect: 200 });
  await get('/ready', { expect: 200 });

  // The web viewer's files (the server's default roots: its build tree's share/locus/web, Debian's Leaflet)
  await get('/', { expect: 200 });
  await get('/web/style.css', { expect: 200 });
  await get('/web/js/main.js', { expect: 200 });
  await get('/vendor/leaflet/leaflet.js', { expect: 200 });
  await get('/vendor/leaflet/images/marker-icon.png', { expect: 200 });
  await get('/web/missing.css', { expect: 404 });
  await get('/web/js/.hidden.js', { expect: 400, invalid: true });
  await get('/vendor/leaflet/leaflet.js.map', { expect: 404 });  // not a type the viewer serves

  // Maps
  const map = idOf(await post('/v1/maps', { name: 'Contract campus', description: 'made by the contract check' }, { expect: 201 }), 'a map');
  const other = idOf(await post('/v1/maps', { name: 'Second campus' }, { expect: 201 }), 'a map');
  await post('/v1/maps', { name: 'Contract campus' }, { expect: 409 });
  await post('/v1/maps', { name: 'No key' }, { auth: false, expect: 401, invalid: true });
  await post('/v1/maps', { name: 'Wrong key' }, { auth: false, headers: { authorization: 'Bearer wrong' }, expect: 401 });
  await post('/v1/maps', { nmae: 'typo' }, { expect: 422, invalid: true });
  await post('/v1/maps', { name: '' }, { expect: 422, invalid: true });
  await post('/v1/maps', { name: 'x', description: null }, { expect: 422, invalid: true });
  await post('/v1/maps', undefined, { raw: '{"name": ', contentType: 'text/plain', expect: 400, invalid: true });
  await post('/v1/maps', undefined, { raw: '[1, 2]', contentType: 'text/plain', expect: 400, invalid: true });
  await get('/v1/maps', { expect: 200 });
  await get('/v1/maps?limit=1&offset=1', { expect: 200 });
  await get('/v1/maps?limit=0', { expect: 400, invalid: true });
  await get('/v1/maps?offset=-1', { expect: 400, invalid: true });
  await get(`/v1/maps/${map}`, { expect: 200 });
  await get(`/v1/maps/${UNKNOWN}`, { expect: 404 });
  await patch(`/v1/maps/${map}`, { description: 'patched' }, { expect: 200 });
  await patch(`/v1/maps/${map}`, {}, { expect: 200 });
  await patch(`/v1/maps/${map}`, { description: null }, { expect: 200 });
  await patch(`/v1/maps/${map}`, { name: 'Second campus' }, { expect: 409 });
  await patch(`/v1/maps/${map}`, { name: null }, { expect: 422, invalid: true });
  await patch(`/v1/maps/${map}`, { colour: 'red' }, { expect: 422, invalid: true });
  await patch(`/v1/maps/${UNKNOWN}`, { description: 'x' }, { expect: 404 });
  await patch(`/v1/maps/${map}`, { description: 'x' }, { auth: false, expect: 401, invalid: true });

  // Buildings
  const building = idOf(await post(`/v1/maps/${map}/buildings`, { name: 'Library' }, { expect: 201 }), 'a building');
  await post(`/v1/maps/${map}/buildings`, { name: 'Library' }, { expect: 409 });
  await post(`/v1/maps/${UNKNOWN}/buildings`, { name: 'Nowhere' }, { expect: 404 });
  await post(`/v1/maps/${map}/buildings`, { name: 'L', floors: 2 }, { expect: 422, invalid: true });
  await get(`/v1/maps/${map}/buildings`, { expect: 200 });
  await get(`/v1/maps/${UNKNOWN}/buildings`, { expect: 404 });
  await get(`/v1/buildings/${building}`, { expect: 200 });
  await get(`/v1/buildings/${UNKNOWN}`, { expect: 404 });
  await patch(`/v1/buildings/${building}`, { description: 'the old library' }, { expect: 200 });
  await patch(`/v1/buildings/${building}`, { name: 42 }, { expect: 422, invalid: true });

  // Floors
  const floor = idOf(await post(`/v1/buildings/${building}/floors`, { name: 'Ground floor', level: 0, width: 30, height: 15, north_offset_deg: 12.5 }, { expect: 201 }), 'a floor');
  const floor2 = idOf(await post(`/v1/buildings/${building}/floors`, { name: 'Basement', level: -1, width: 30, height: 15 }, { expect: 201 }), 'a floor');
  await post(`/v1/buildings/${building}/floors`, { name: 'Flat', level: 1, width: 0, height: 15 }, { expect: 422, invalid: true });
  await post(`/v1/buildings/${building}/floors`, { name: 'Half', level: 1.5, width: 3, height: 15 }, { expect: 422, invalid: true });
  await post(`/v1/buildings/${building}/floors`, { name: 'No size', level: 1 }, { expect: 422, invalid: true });
  await post(`/v1/buildings/${UNKNOWN}/floors`, { name: 'Nowhere', level: 0, width: 1, height: 1 }, { expect: 404 });
  await get(`/v1/buildings/${building}/floors?limit=1`, { expect: 200 });
  await get(`/v1/buildings/${UNKNOWN}/floors`, { expect: 404 });
  await get(`/v1/floors/${floor}`, { expect: 200 });
  await patch(`/v1/floors/${floor}`, { north_offset_deg: 10 }, { expect: 200 });
  await patch(`/v1/floors/${floor}`, { north_offset_deg: null }, { expect: 200 });
  await patch(`/v1/floors/${floor}`, { level: 2000 }, { expect: 422, invalid: true });
  await patch(`/v1/floors/${floor}`, { name: 'Basement' }, { expect: 409 });
  // Floors on Earth (docs/geo.md): set, cleared, refused, fitted from control points. The floor
  // stays georeferenced, so the localize, track and route answers below carry lat/lon.
  await patch(`/v1/floors/${floor}`, { geo: { lat: 49.46115181, lon: 11.11114911, x: 15, y: 7.5, bearing_deg: -20.736 }, elevation_m: 0 }, { expect: 200 });
  await patch(`/v1/floors/${floor2}`, { geo: null, elevation_m: -3.5 }, { expect: 200 });
  await patch(`/v1/floors/${floor}`, { geo: { lat: 91, lon: 11, x: 0, y: 0, bearing_deg: 0 } }, { expect: 422, invalid: true });
  await patch(`/v1/floors/${floor}`, { geo: { lat: 49.46, lon: 11.11, x: 0, y: 0 } }, { expect: 422, invalid: true });
  await patch(`/v1/floors/${floor}`, { elevation_m: 20000 }, { expect: 422, invalid: true });
  const control = [
    { x: 0, y: 0, lat: 49.4610374, lon: 11.1109761 },
    { x: 30, y: 0, lat: 49.4609839, lon: 11.1113633 },
    { x: 30, y: 15, lat: 49.4611101, lon: 11.1114342 },
  ];
  await post(`/v1/floors/${floor}/georeference?dry_run=true`, { points: control }, { expect: 200 });
  await post(`/v1/floors/${floor}/georeference`, { points: control }, { expect: 200 });
  await post(`/v1/floors/${floor}/georeference`, { points: control.slice(0, 2) }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor}/georeference`, { points: [control[0], { ...control[1], lat: 95 }, control[2]] }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor}/georeference`, { points: [control[0], { ...control[1], z: 1 }, control[2]] }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor}/georeference`, { points: [{ x: 0, y: 0, lat: 49.46, lon: 11.11 }, { x: 10, y: 0, lat: 49.46, lon: 11.1101 }, { x: 20, y: 0, lat: 49.46, lon: 11.1102 }] }, { expect: 422 });
  await post(`/v1/floors/${floor}/georeference?dry_run=maybe`, { points: control }, { expect: 400, invalid: true });
  await post(`/v1/floors/${UNKNOWN}/georeference`, { points: control }, { expect: 404 });

  // Rooms
  const room = idOf(await post(`/v1/floors/${floor}/rooms`, { name: 'Lobby', rects: [{ xmin: 0, ymin: 0, xmax: 15, ymax: 15 }] }, { expect: 201 }), 'a room');
  await post(`/v1/floors/${floor}/rooms`, { name: 'Nothing', rects: [] }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor}/rooms`, { name: 'Extra', rects: [{ xmin: 0, ymin: 0, xmax: 1, ymax: 1, z: 0 }] }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor}/rooms`, { name: 'Far', rects: [{ xmin: 0, ymin: 0, xmax: 2e7, ymax: 1 }] }, { expect: 422, invalid: true });
  await get(`/v1/floors/${floor}/rooms`, { expect: 200 });
  await get(`/v1/floors/${UNKNOWN}/rooms`, { expect: 404 });
  await get(`/v1/rooms/${room}`, { expect: 200 });
  await patch(`/v1/rooms/${room}`, { name: 'Entrance hall' }, { expect: 200 });
  await patch(`/v1/rooms/${room}`, { rects: [{ xmin: 0, ymin: 0, xmax: 10, ymax: 15 }, { xmin: 10, ymin: 0, xmax: 15, ymax: 5 }] }, { expect: 200 });
  await patch(`/v1/rooms/${UNKNOWN}`, { name: 'x' }, { expect: 404 });

  // Points of interest
  const poi = idOf(await post(`/v1/floors/${floor}/pois`, { name: 'Main exit', kind: 'exit', x: 0.5, y: 7.5 }, { expect: 201 }), 'a POI');
  await post(`/v1/floors/${floor}/pois`, { name: 'No place' }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor}/pois`, { name: 'Main exit', x: 1, y: 1 }, { expect: 409 });
  await get(`/v1/floors/${floor}/pois`, { expect: 200 });
  await get(`/v1/pois/${poi}`, { expect: 200 });
  await patch(`/v1/pois/${poi}`, { kind: 'emergency_exit' }, { expect: 200 });
  await patch(`/v1/pois/${poi}`, { x: '1' }, { expect: 422, invalid: true });

  // Transmitters (docs/transmitters.md): three APs and a beacon at known positions on the 30 m × 15 m floor
  const txAp = (n) => `02:00:00:00:10:0${n}`;
  const tx = idOf(await post(`/v1/floors/${floor}/transmitters`, { name: 'AP west', type: 'wifi', bssid: txAp(1), x: 2, y: 2, z: 2.6, tx_power: -40, path_loss_exponent: 2 }, { expect: 201 }), 'a transmitter');
  await post(`/v1/floors/${floor}/transmitters`, { type: 'wifi', bssid: txAp(2), x: 28, y: 2, tx_power: -40 }, { expect: 201 });
  await post(`/v1/floors/${floor}/transmitters`, { type: 'wifi', bssid: txAp(3), x: 15, y: 13, tx_power: -40, wall_attenuation: 4 }, { expect: 201 });
  await post(`/v1/floors/${floor}/transmitters`, { ibeacon: { uuid: 'f7826da6-4fa2-4e98-8024-bc5b71e0893e', major: 1, minor: 2 }, x: 10, y: 7, tx_power: -59 }, { expect: 201 });
  await post(`/v1/floors/${floor}/transmitters`, { eddystone: { namespace: 'edd1ebeac04e5defa017', instance: '0123456789ab' }, x: 20, y: 7, tx_power: -62 }, { expect: 201 });
  await post(`/v1/floors/${floor}/transmitters`, { type: 'wifi', bssid: txAp(1), x: 5, y: 5, tx_power: -40 }, { expect: 409 });
  await post(`/v1/floors/${floor}/transmitters`, { type: 'wifi', bssid: txAp(4), x: 31, y: 5, tx_power: -40 }, { expect: 422 });
  await post(`/v1/floors/${floor}/transmitters`, { type: 'wifi', bssid: txAp(4), x: 5, y: -1, tx_power: -40 }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor}/transmitters`, { type: 'wifi', bssid: txAp(4), x: 5, y: 5 }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor}/transmitters`, { ibeacon: { uuid: 'xyz', major: 1, minor: 2 }, x: 5, y: 5, tx_power: -59 }, { expect: 422, invalid: true });
  await post(`/v1/floors/${UNKNOWN}/transmitters`, { type: 'wifi', bssid: txAp(4), x: 5, y: 5, tx_power: -40 }, { expect: 404 });
  await get(`/v1/floors/${floor}/transmitters`, { expect: 200 });
  await get(`/v1/floors/${UNKNOWN}/transmitters`, { expect: 404 });
  await get(`/v1/transmitters/${tx}`, { expect: 200 });
  await patch(`/v1/transmitters/${tx}`, { tx_power: -41, path_loss_exponent: 2.2 }, { expect: 200 });
  await patch(`/v1/transmitters/${tx}`, { path_loss_exponent: 'steep' }, { expect: 422, invalid: true });
  await patch(`/v1/transmitters/${tx}`, { x: 40 }, { expect: 422 });
  await post(`/v1/floors/${floor}/transmitters/fit`, { min_rps: 4 }, { expect: 200 });
  await post(`/v1/floors/${floor}/transmitters/fit?apply=true`, {}, { expect: 200 });
  await post(`/v1/floors/${floor}/transmitters/fit`, { transmitters: [tx] }, { expect: 422 });
  await post(`/v1/floors/${floor}/transmitters/fit`, { min_rps: 1 }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor}/transmitters/fit?apply=yes`, {}, { expect: 400, invalid: true });
  await post(`/v1/floors/${UNKNOWN}/transmitters/fit`, {}, { expect: 404 });
  await post(`/v1/floors/${floor2}/radiomaps/generate`, { name: 'Modelled', step: 5 }, { expect: 422 });
  const modelled = idOf(await post(`/v1/floors/${floor}/radiomaps/generate`, { name: 'Modelled', step: 2.5, min_rss: -100, sigma_db: 3, phone_height: 1 }, { expect: 201 }), 'a radio map');
  await post(`/v1/radiomaps/${modelled}/densify`, { step: 2, sigma_db: 3 }, { expect: 200 });
  await post(`/v1/radiomaps/${modelled}/densify`, { step: 0 }, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${modelled}/densify`, { step: 2, colour: 1 }, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${UNKNOWN}/densify`, { step: 2 }, { expect: 404 });
  await post(`/v1/floors/${floor}/radiomaps/generate`, { name: 'Modelled', step: 2.5 }, { expect: 409 });
  await post(`/v1/floors/${floor}/radiomaps/generate`, { name: 'Too fine', step: 0.01 }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor}/radiomaps/generate`, { step: 1 }, { expect: 422, invalid: true });
  await post(`/v1/floors/${UNKNOWN}/radiomaps/generate`, { name: 'x', step: 1 }, { expect: 404 });

  // Radio maps and reference points
  const radiomap = idOf(await post(`/v1/floors/${floor}/radiomaps`, { name: 'Survey 2026' }, { expect: 201 }), 'a radio map');
  const radiomap2 = idOf(await post(`/v1/floors/${floor2}/radiomaps`, { name: 'Basement survey', description: 'no rooms here' }, { expect: 201 }), 'a radio map');
  await post(`/v1/floors/${floor}/radiomaps`, { name: 'Survey 2026' }, { expect: 409 });
  await post(`/v1/floors/${UNKNOWN}/radiomaps`, { name: 'x' }, { expect: 404 });
  await get(`/v1/floors/${floor}/radiomaps`, { expect: 200 });
  await get(`/v1/radiomaps/${radiomap}`, { expect: 200 });
  await patch(`/v1/radiomaps/${radiomap}`, { description: 're-surveyed' }, { expect: 200 });
  await patch(`/v1/radiomaps/${radiomap}`, { description: 'x'.repeat(4001) }, { expect: 422, invalid: true });

  const rp1 = idOf(await post(`/v1/radiomaps/${radiomap}/rps`, { name: 'door', x: 1, y: 7.5 }, { expect: 201 }), 'an RP');
  const rp2 = idOf(await post(`/v1/radiomaps/${radiomap}/rps`, { name: 'desk', x: 12, y: 3 }, { expect: 201 }), 'an RP');
  const rp3 = idOf(await post(`/v1/radiomaps/${radiomap2}/rps`, { name: 'stairs', x: 5, y: 5 }, { expect: 201 }), 'an RP');
  await post(`/v1/radiomaps/${radiomap}/rps`, { name: 'door', x: 2, y: 2 }, { expect: 409 });
  await post(`/v1/radiomaps/${radiomap}/rps`, { name: 'far', x: 1e8, y: 2 }, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${UNKNOWN}/rps`, { name: 'x', x: 1, y: 1 }, { expect: 404 });
  await get(`/v1/radiomaps/${radiomap}/rps`, { expect: 200 });
  await get(`/v1/radiomaps/${UNKNOWN}/rps`, { expect: 404 });
  await patch(`/v1/rps/${rp2}`, { x: 12.5 }, { expect: 200 });
  await patch(`/v1/rps/${rp2}`, { z: 1 }, { expect: 422, invalid: true });

  // Survey uploads
  const upload = { upload_id: 'door-1', scans: [scan([1, -45], [2, -70]), scan([1, -47], [2, -72], [3, -80])] };
  await post(`/v1/rps/${rp1}/scans`, upload, { expect: 200 });
  await post(`/v1/rps/${rp1}/scans`, upload, { expect: 200 });
  await post(`/v1/rps/${rp2}/scans`, { scans: [[{ type: 'wifi', bssid: ap(1), rss: -75 }, { bssid: ap(2).toUpperCase(), rss: -50 }, { type: 'ble', bssid: 'beacon-7', rss: -60 }], []] }, { expect: 200 });
  await post(`/v1/rps/${rp3}/scans`, { measurements: [{ bssid: ap(9), mean: -60, variance: 4, count: 3 }, { type: 'wifi', bssid: ap(1), mean: -90, variance: 0, count: 1 }] }, { expect: 200 });
  await post(`/v1/rps/${rp3}/scans`, { upload_id: 'empty', measurements: [] }, { expect: 200 });
  await post(`/v1/rps/${rp1}/scans`, { scans: [scan([1, -40])], measurements: [] }, { expect: 422, invalid: true });
  await post(`/v1/rps/${rp1}/scans`, { scans: [] }, { expect: 422, invalid: true });
  await post(`/v1/rps/${rp1}/scans`, { scans: [scan([1, -130])] }, { expect: 422, invalid: true });
  await post(`/v1/rps/${rp1}/scans`, { scans: [[{ bssid: ap(1), rss: -40, ssid: 'x' }]] }, { expect: 422, invalid: true });
  await post(`/v1/rps/${rp1}/scans`, { scans: [[{ bssid: '   ', rss: -40 }]] }, { expect: 422, invalid: true });
  await post(`/v1/rps/${rp1}/scans`, { measurements: [{ bssid: ap(1), mean: -60, variance: 4000, count: 2 }] }, { expect: 422, invalid: true });
  await post(`/v1/rps/${rp1}/scans`, { measurements: [{ bssid: ap(1), mean: -60, variance: 1, count: 0 }] }, { expect: 422, invalid: true });
  await post(`/v1/rps/${UNKNOWN}/scans`, { scans: [scan([1, -40])] }, { expect: 404 });
  await post(`/v1/rps/${rp1}/scans`, { scans: [scan([1, -40])] }, { auth: false, expect: 401, invalid: true });
  await get(`/v1/rps/${rp1}`, { expect: 200 });
  await get(`/v1/rps/${UNKNOWN}`, { expect: 404 });
  await get(`/v1/radiomaps/${radiomap}/rps`, { expect: 200 });  // last_upload_at: a time and null
  await get(`/v1/radiomaps/${radiomap}/quality`, { expect: 200 });
  await get(`/v1/radiomaps/${radiomap}/quality?folds=1`, { expect: 400, invalid: true });

  // Export and import
  const exported = await get(`/v1/radiomaps/${radiomap}/export`, { expect: 200 });
  await get(`/v1/radiomaps/${UNKNOWN}/export`, { expect: 404 });
  const doc = { ...(exported.json || {}), name: 'Survey 2026 (copy)' };
  await post(`/v1/floors/${floor2}/radiomaps/import`, doc, { expect: 201 });
  await post(`/v1/floors/${floor2}/radiomaps/import`, doc, { expect: 409 });
  await post(`/v1/floors/${floor2}/radiomaps/import`, { name: 'Minimal', rps: [] }, { expect: 201 });
  await post(`/v1/floors/${floor2}/radiomaps/import`, { name: 'Twice', rps: [{ name: 'a', x: 0, y: 0 }, { name: 'a', x: 1, y: 1 }] }, { expect: 409 });
  await post(`/v1/floors/${floor2}/radiomaps/import`, { name: 'Bad RP', rps: [{ name: 'a', x: 0, y: 0, z: 1 }] }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor2}/radiomaps/import`, { format: 'locus-radiomap/2', name: 'Future', rps: [] }, { expect: 422, invalid: true });
  await post(`/v1/floors/${floor2}/radiomaps/import`, { name: 'No RPs' }, { expect: 422, invalid: true });
  await post(`/v1/floors/${UNKNOWN}/radiomaps/import`, { name: 'Nowhere', rps: [] }, { expect: 404 });

  // Localize (open: no key)
  const live = { scans: [scan([1, -46], [2, -71])] };
  await post(`/v1/radiomaps/${radiomap}/localize`, { algorithm: 'wknn', ...live }, { expect: 200 });
  for (const algorithm of ['bsb', 'nn', 'bsbnn', 'knn', 'bayes'])
    await post(`/v1/radiomaps/${radiomap}/localize`, { algorithm, ...live }, { expect: 200 });
  await post(`/v1/radiomaps/${radiomap}/localize`, { ...live, options: { k: 2, estimate: 'map', tolerance: 0.5, candidates: 1, near: { x: 1, y: 7, radius: 50 } } }, { expect: 200 });
  await post(`/v1/radiomaps/${radiomap}/localize`, { measurements: [{ bssid: ap(1), mean: -46 }, { type: 'wifi', bssid: ap(2), rss: -71 }] }, { expect: 200 });
  await post(`/v1/radiomaps/${radiomap2}/localize`, { scans: [scan([9, -61])] }, { expect: 200 });
  await post(`/v1/radiomaps/${radiomap}/localize`, { scans: [scan([77, -50])] }, { expect: 422 });
  await post(`/v1/radiomaps/${radiomap}/localize`, { ...live, options: { near: { x: 500, y: 500, radius: 1 } } }, { expect: 422 });
  await post(`/v1/radiomaps/${radiomap}/localize`, { ...live, limit: 3 }, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${radiomap}/localize`, { ...live, options: { k: 0 } }, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${radiomap}/localize`, { ...live, options: { metric: 'cosine' } }, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${radiomap}/localize`, { algorithm: 'bayes', ...live, options: { floor_knn: 3, floor_knn_position: false } }, { expect: 200 });
  await post(`/v1/radiomaps/${radiomap}/localize`, { ...live, options: { floor_knn_position: 'no' } }, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${radiomap}/localize`, { algorithm: 'magic', ...live }, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${radiomap}/localize`, { ...live, measurements: [{ bssid: ap(1), rss: -40 }] }, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${radiomap}/localize`, {}, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${radiomap}/localize`, undefined, { raw: '{"scans": [[', contentType: 'text/plain', expect: 400, invalid: true });
  await post(`/v1/radiomaps/${UNKNOWN}/localize`, live, { expect: 404 });
  await post(`/v1/maps/${map}/localize`, live, { expect: 200 });
  await post(`/v1/maps/${map}/localize`, { algorithm: 'wknn', scans: [scan([9, -60])] }, { expect: 200 });
  await post(`/v1/maps/${other}/localize`, live, { expect: 422 });
  // Ranging from the floor's transmitters (three APs about 8 m from (8, 6))
  const ranged = { measurements: [{ bssid: txAp(1), rss: -57 }, { bssid: txAp(2), rss: -68 }, { bssid: txAp(3), rss: -62 }] };
  await post(`/v1/radiomaps/${radiomap}/localize`, { algorithm: 'multilateration', ...ranged }, { expect: 200 });
  await post(`/v1/maps/${map}/localize`, { algorithm: 'multilateration', ...ranged, options: { sigma_db: 3, loss_scale: 2, max_iterations: 50, phone_height: 1 } }, { expect: 200 });
  await post(`/v1/radiomaps/${radiomap}/localize`, { algorithm: 'trilateration', ...ranged, options: { cutoff: 30, vote_slack: 1.25, correct: true, max_transmitters: 12 } }, { expect: 200 });
  await post(`/v1/radiomaps/${radiomap}/localize`, { algorithm: 'trilateration', ...ranged }, { expect: 422 });
  await post(`/v1/radiomaps/${radiomap}/localize`, { algorithm: 'multilateration', measurements: [{ bssid: txAp(1), rss: -57 }] }, { expect: 422 });
  await post(`/v1/radiomaps/${radiomap}/localize`, { algorithm: 'multilateration', ...ranged, options: { cutoff: -1 } }, { expect: 422, invalid: true });
  await post(`/v1/maps/${UNKNOWN}/localize`, live, { expect: 404 });
  // Self-tuning: a CV over the radio map's own RPs, stored as its settings.
  await post(`/v1/radiomaps/${radiomap}/tune`, {}, { expect: 200 });
  await get(`/v1/radiomaps/${radiomap}`, { expect: 200 });
  await post(`/v1/radiomaps/${radiomap}/localize`, live, { expect: 200 });
  await post(`/v1/radiomaps/${radiomap}/tune`, { folds: 1 }, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${radiomap}/tune`, { fold: 3 }, { expect: 422, invalid: true });
  await post(`/v1/radiomaps/${radiomap2}/tune`, { folds: 5 }, { expect: 422 });
  await post(`/v1/radiomaps/${UNKNOWN}/tune`, {}, { expect: 404 });
  // The predicted-error layer: each RP's held-out error with the settings just tuned.
  await get(`/v1/radiomaps/${radiomap}/quality`, { expect: 200 });
  await get(`/v1/radiomaps/${radiomap}/quality?folds=3&max_queries=10`, { expect: 200 });
  await get(`/v1/radiomaps/${radiomap}/quality?folds=1`, { expect: 400, invalid: true });
  await get(`/v1/radiomaps/${radiomap2}/quality`, { expect: 422 });
  await get(`/v1/radiomaps/${UNKNOWN}/quality`, { expect: 404 });
  await post(`/v1/radiomaps/${radiomap}/tune`, {}, { auth: false, expect: 401, invalid: true });
  // Over the server's --max-body-bytes (the script starts it with 64 KiB), yet valid.
  const big = { scans: [Array.from({ length: 3000 }, (_, i) => ({ bssid: `aa:bb:cc:dd:${String(i % 100).padStart(2, '0')}:${String(i % 97).padStart(2, '0')}`, rss: -50 }))] };
  await post(`/v1/maps/${map}/localize`, big, { expect: 413 });
  await post('/v1/maps', { name: 'Big', description: 'd'.repeat(3000) }, { expect: 201 });
  await post(`/v1/floors/${floor2}/radiomaps/import`, { name: 'Huge', rps: Array.from({ length: 4000 }, (_, i) => ({ name: `rp${i}`, x: i, y: 0 })) }, { expect: 413 });

  // Floor plans: the ground floor's stairs link to the basement's, which must link back.
  const feature = (geometry, properties) => ({ type: 'Feature', geometry, properties });
  // The ground floor's Lobby keeps the room made above (room_id); the basement's spaces and
  // every connector get rooms and POIs of their own.
  const plan = (links, lobbyRoom) => ({
    type: 'FeatureCollection',
    features: [
      feature({ type: 'Polygon', coordinates: [[[0, 0], [15, 0], [15, 15], [0, 15], [0, 0]]] }, { feature: 'space', name: 'Lobby', kind: 'hall', tags: ['Reception'], room_id: lobbyRoom }),
      feature({ type: 'Polygon', coordinates: [[[15, 0], [30, 0], [30, 15], [15, 15], [15, 0]], [[20, 5], [21, 5], [21, 6], [20, 5]]] }, { feature: 'space', name: 'Reading room' }),
      feature({ type: 'LineString', coordinates: [[15, 0], [15, 15]] }, { feature: 'wall' }),
      feature({ type: 'Point', coordinates: [15, 7.5] }, { feature: 'door', name: 'Reading room door' }),
      feature({ type: 'LineString', coordinates: [[15, 1], [15, 2]] }, { feature: 'door' }),
      feature({ type: 'Point', coordinates: [2, 2] }, { feature: 'connector', id: 's1', kind: 'stairs', name: 'Main stairs', links }),
      feature({ type: 'Point', coordinates: [3, 2] }, { feature: 'connector', id: 'e1', kind: 'elevator', seconds_per_level: 20 }),
    ],
  });
  await get(`/v1/floors/${floor}/plan`, { expect: 404 });
  const ground = await put(`/v1/floors/${floor}/plan`, plan([{ floor_id: floor2, connector: 's1' }], room), { expect: 200 });
  await put(`/v1/floors/${floor2}/plan`, plan([{ floor_id: floor, connector: 'nowhere' }]), { expect: 422 });
  await put(`/v1/floors/${floor2}/plan`, plan([{ floor_id: floor, connector: 's1' }]), { expect: 200 });
  await get(`/v1/floors/${floor}/plan`, { expect: 200 });
  await put(`/v1/floors/${floor}/plan`, ground.json, { expect: 200 });
  await put(`/v1/floors/${floor}/plan`, { type: 'FeatureCollection', features: [feature({ type: 'Point', coordinates: [1, 1] }, { feature: 'window' })] }, { expect: 422, invalid: true });
  await put(`/v1/floors/${floor}/plan`, { type: 'FeatureCollection', features: [feature({ type: 'LineString', coordinates: [[0, 0], [2e5, 0]] }, { feature: 'wall' })] }, { expect: 422, invalid: true });
  await put(`/v1/floors/${floor}/plan`, { type: 'FeatureCollection', features: [feature({ type: 'LineString', coordinates: [[0, 0], [1, 0]] }, { feature: 'wall', colour: 'red' })] }, { expect: 422, invalid: true });
  await put(`/v1/floors/${floor}/plan`, { features: [] }, { expect: 422, invalid: true });
  await put(`/v1/floors/${floor}/plan`, plan([]), { auth: false, expect: 401, invalid: true });
  await put(`/v1/floors/${UNKNOWN}/plan`, plan([]), { expect: 404 });
  await get(`/v1/floors/${UNKNOWN}/plan`, { expect: 404 });
  // A room the plan keeps changes only through the plan.
  await patch(`/v1/rooms/${room}`, { name: 'Hall' }, { expect: 409 });
  await del(`/v1/rooms/${room}`, { expect: 409 });
  await put(`/v1/floors/${floor}/plan`, plan([], UNKNOWN), { expect: 422 });
  // Routes: from the lobby up the stairs to the basement's reading room, and the refusals.
  await post(`/v1/maps/${map}/route`, { from: { room_id: room }, to: { floor_id: floor2, x: 25, y: 10 } }, { expect: 200 });
  await post(`/v1/maps/${map}/route`, { from: { poi_id: poi }, to: { floor_id: floor, x: 25, y: 10 }, options: { step_free: true, avoid: [room], walking_speed: 1.1 } }, { expect: 200 });
  await post(`/v1/maps/${map}/route`, { from: { floor_id: floor, x: 1, y: 1 }, to: { floor_id: floor, x: 29, y: 29 } }, { expect: 422 });
  await post(`/v1/maps/${map}/route`, { from: { floor_id: floor, x: 1, y: 1 } }, { expect: 422, invalid: true });
  await post(`/v1/maps/${map}/route`, { from: { floor_id: floor, x: 1e6, y: 1 }, to: { room_id: room } }, { expect: 422, invalid: true });
  await post(`/v1/maps/${map}/route`, { from: { room_id: room }, to: { room_id: room }, options: { lift: true } }, { expect: 422, invalid: true });
  await post(`/v1/maps/${map}/route`, { from: { room_id: UNKNOWN }, to: { room_id: room } }, { expect: 422 });
  await post(`/v1/maps/${UNKNOWN}/route`, { from: { room_id: room }, to: { room_id: room } }, { expect: 404 });
  // The directory: the lobby's room by its plan tag, the reading-room space by a typo, and a
  // hit's route_to posted back as a route's `to`; then the refusals.
  const search = (q, rest = '') => `/v1/maps/${map}/search?q=${encodeURIComponent(q)}${rest}`;
  await get(search('réception'), { expect: 200 });
  const found = await get(search('readng room', '&limit=1'), { expect: 200 });
  const hit = found.json && found.json.hits && found.json.hits[0];
  if (!hit) violations.push('GET search: the reading room was not found');
  else await post(`/v1/maps/${map}/route`, { from: { room_id: room }, to: hit.route_to }, { expect: 200 });
  await get(`/v1/maps/${map}/search`, { expect: 400, invalid: true });
  await get(search(''), { expect: 400, invalid: true });
  await get(search('   '), { expect: 400 });
  await get(search('lobby', '&limit=0'), { expect: 400, invalid: true });
  await get(search('lobby', '&limit=many'), { expect: 400, invalid: true });
  await get(`/v1/maps/${UNKNOWN}/search?q=lobby`, { expect: 404 });
  // Live tracks: two phones on the map, one sharing with the other; fixes, the trail, the
  // relative position over the plans, the operator's positions, the event stream of a closed
  // track (its latest fix and its end), then the refusals. Tracks take their own token, not
  // the API key.
  {
    const nowS = Date.now() / 1000;
    const fixOf = (t, fl, x, y, h) => ({ t, floor_id: fl, x, y, accuracy_m: 1.5, ...(h === undefined ? {} : { heading_deg: h }) });
    const openedA = await post('/v1/tracks', { map_id: map, label: 'Ann' }, { auth: false, expect: 201 });
    const openedB = await post('/v1/tracks', { map_id: map }, { auth: false, expect: 201 });
    const a = openedA.json?.id ?? UNKNOWN;
    const b = openedB.json?.id ?? UNKNOWN;
    const ta = { 'x-track-token': openedA.json?.token ?? '' };
    const tb = { 'x-track-token': openedB.json?.token ?? '' };
    const own = (headers, opts = {}) => ({ auth: false, headers, ...opts });
    await post(`/v1/tracks/${a}/fixes`, { fixes: [fixOf(nowS - 2, floor, 5, 5, 90), fixOf(nowS - 3, floor, 4, 5)] }, own(ta, { expect: 200 }));
    await post(`/v1/tracks/${a}/fixes`, { fixes: [fixOf(nowS - 2, floor, 5, 5, 90)] }, own(ta, { expect: 200 }));
    await post(`/v1/tracks/${b}/fixes`, { fixes: [fixOf(nowS - 1, floor2, 25, 10)] }, own(tb, { expect: 200 }));
    const share = await post(`/v1/tracks/${b}/shares`, {}, own(tb, { expect: 201 }));
    const sb = { 'x-track-token': share.json?.token ?? '' };
    await get(`/v1/tracks/${a}?limit=10`, { headers: ta, expect: 200 });
    await get(`/v1/tracks/${b}`, { headers: sb, expect: 200 });
    await get(`/v1/tracks/${a}/relative/${b}`, { headers: { ...ta, 'x-peer-token': sb['x-track-token'] }, expect: 200 });
    await get(`/v1/maps/${map}/positions`, { auth: true, expect: 200 });
    await get(`/v1/maps/${map}/positions?floor_id=${floor2}`, { auth: true, expect: 200 });
    await get(`/v1/maps/${map}/positions`, { expect: 401, invalid: true });
    await get(`/v1/maps/${map}/positions?floor_id=x`, { auth: true, expect: 400, invalid: true });
    await get(`/v1/maps/${UNKNOWN}/positions`, { auth: true, expect: 404 });
    await get(`/v1/maps/${map}/positions/events?floor_id=${floor2}`, { auth: true, expect: 200, direct: true, stream: true });
    await get(`/v1/maps/${map}/positions/events`, { expect: 401, invalid: true });
    await get(`/v1/maps/${map}/positions/events?floor_id=0`, { auth: true, expect: 400, invalid: true });
    await get(`/v1/maps/${UNKNOWN}/positions/events`, { auth: true, expect: 404 });
    await post('/v1/tracks', { map_id: UNKNOWN }, { auth: false, expect: 422 });
    await post('/v1/tracks', { map_id: map, colour: 'red' }, { auth: false, expect: 422, invalid: true });
    const openedC = await post('/v1/tracks', { map_id: map, fusion: 'particle' }, { auth: false, expect: 201 });
    const c = openedC.json?.id ?? UNKNOWN;
    const tc = { 'x-track-token': openedC.json?.token ?? '' };
    await post('/v1/tracks', { map_id: map, fusion: 'kalman' }, { auth: false, expect: 422, invalid: true });
    // A Kalman track: its scans ranged on the floor's transmitters (multilateration), fused with
    // a step; a scan hearing two of them, and noise options out of range or for another method.
    const openedK = await post('/v1/tracks', { map_id: map, fusion: 'kalman_ranging', fusion_options: { r_floor_m: 0.5, q_sigma_per_m: 0.3 } }, { auth: false, expect: 201 });
    const k = openedK.json?.id ?? UNKNOWN;
    const tk = { 'x-track-token': openedK.json?.token ?? '' };
    const txScan = (pairs) => pairs.map(([i, rss]) => ({ type: 'wifi', bssid: txAp(i), rss }));
    await post(`/v1/tracks/${k}/steps`, { scans: [{ t: nowS - 1.2, readings: txScan([[1, -55], [2, -68], [3, -63]]) }], steps: [{ t: nowS - 1, length_m: 0.7, heading_deg: 90 }] }, own(tk, { expect: 200 }));
    await get(`/v1/tracks/${k}`, { headers: tk, expect: 200 });
    await post(`/v1/tracks/${k}/steps`, { scans: [{ t: nowS - 0.9, readings: txScan([[1, -55], [2, -68]]) }] }, own(tk, { expect: 422 }));
    // An ekf_ranging track: a scan of two known transmitters refused before it runs, then a
    // ranged scan starts it, a step and a scan of two are fused; an option of another method.
    const openedE = await post('/v1/tracks', { map_id: map, fusion: 'ekf_ranging', fusion_options: { reading_sigma_db: 4, step_lead_s: 0.7 } }, { auth: false, expect: 201 });
    const ekfT = openedE.json?.id ?? UNKNOWN;
    const te = { 'x-track-token': openedE.json?.token ?? '' };
    await post(`/v1/tracks/${ekfT}/steps`, { scans: [{ t: nowS - 1.3, readings: txScan([[1, -55], [2, -68]]) }] }, own(te, { expect: 422 }));
    await post(`/v1/tracks/${ekfT}/steps`, { scans: [{ t: nowS - 1.2, readings: txScan([[1, -55], [2, -68], [3, -63]]) }, { t: nowS - 0.9, readings: txScan([[1, -56], [2, -67]]) }], steps: [{ t: nowS - 1, length_m: 0.7, heading_deg: 90 }] }, own(te, { expect: 200 }));
    await get(`/v1/tracks/${ekfT}`, { headers: te, expect: 200 });
    await post('/v1/tracks', { map_id: map, fusion: 'ekf_ranging', fusion_options: { r_floor_m: 0.5 } }, { auth: false, expect: 422 });
    await post('/v1/tracks', { map_id: map, fusion: 'ekf_ranging', fusion_options: { reading_sigma_db: 0 } }, { auth: false, expect: 422, invalid: true });
    await post('/v1/tracks', { map_id: map, fusion: 'kalman_trilateration', fusion_options: { r_sigma_m: -1 } }, { auth: false, expect: 422, invalid: true });
    // The deprecated alias kalman_seed opens a kalman_trilateration track, named so in the answer.
    const openedAlias = await post('/v1/tracks', { map_id: map, fusion: 'kalman_seed', fusion_options: { r_sigma_m: 2.5 } }, { auth: false, expect: 201 });
    if (openedAlias.json?.fusion !== 'kalman_trilateration')
      violations.push(`POST /v1/tracks with fusion kalman_seed: answered fusion ${openedAlias.json?.fusion}, not kalman_trilateration`);
    await post('/v1/tracks', { map_id: map, fusion: 'walk_pf', fusion_options: { q_sigma_m: 0.3 } }, { auth: false, expect: 422 });
    await post(`/v1/tracks/${a}/fixes`, { fixes: [fixOf(nowS, floor, 1, 1)] }, { auth: false, expect: 401 });
    await post(`/v1/tracks/${a}/fixes`, { fixes: [fixOf(nowS, floor, 1, 1)] }, own(tb, { expect: 403 }));
    await post(`/v1/tracks/${a}/fixes`, { fixes: [fixOf(nowS, floor, 1, 1)] }, own(sb, { expect: 403 }));
    await post(`/v1/tracks/${a}/fixes`, { fixes: [fixOf(nowS, UNKNOWN, 1, 1)] }, own(ta, { expect: 422 }));
    await post(`/v1/tracks/${a}/fixes`, { fixes: [fixOf(nowS + 3600, floor, 1, 1)] }, own(ta, { expect: 422 }));
    await post(`/v1/tracks/${a}/fixes`, { fixes: [{ t: nowS, floor_id: floor, x: 1, y: 1 }] }, own(ta, { expect: 422, invalid: true }));
    await post(`/v1/tracks/${a}/fixes`, { fixes: [fixOf(nowS, floor, 1e6, 1)] }, own(ta, { expect: 422, invalid: true }));
    await post(`/v1/tracks/${a}/fixes`, { fixes: Array.from({ length: 1001 }, (_, i) => fixOf(nowS - 20 + i / 100, floor, 1, 1)) }, own(ta, { expect: 413, invalid: true }));
    // A thin client: a radio fix and steps, fused on the server over the ground floor's plan.
    await post(`/v1/tracks/${a}/steps`, { fixes: [fixOf(nowS - 1.5, floor, 5, 5)], steps: [{ t: nowS - 1, length_m: 0.7, heading_deg: 90 }] }, own(ta, { expect: 200 }));
    // Steps on a track with no fix at all: nowhere to start (422 cannot_fuse).
    await post(`/v1/tracks/${c}/steps`, { steps: [{ t: nowS - 0.5, length_m: 0.7, heading_deg: 90 }] }, own(tc, { expect: 422 }));
    await post(`/v1/tracks/${a}/steps`, { steps: [{ t: nowS, length_m: 7, heading_deg: 90 }] }, own(ta, { expect: 422, invalid: true }));
    await post(`/v1/tracks/${a}/steps`, { walk: [] }, own(ta, { expect: 422, invalid: true }));
    // A thin client's scan, localized on the track's map and fused as its radio fix.
    await post(`/v1/tracks/${a}/steps`, { scans: [{ t: nowS - 0.8, readings: scan([1, -46], [2, -71]) }], steps: [{ t: nowS - 0.7, length_m: 0.7, heading_deg: 90 }] }, own(ta, { expect: 200 }));
    await post(`/v1/tracks/${a}/steps`, { scans: [{ t: nowS - 0.6, readings: [{ bssid: ap(1), rss: 20 }] }] }, own(ta, { expect: 422, invalid: true }));
    await post(`/v1/tracks/${a}/steps`, { scans: [{ t: nowS - 0.6, readings: [] }] }, own(ta, { expect: 422, invalid: true }));
    await post(`/v1/tracks/${a}/steps`, { scans: [{ t: nowS - 0.6, readings: scan([77, -50]) }] }, own(ta, { expect: 422 }));
    await get(`/v1/tracks/${UNKNOWN}`, { headers: ta, expect: 403 });
    await get(`/v1/tracks/${a}`, { expect: 401 });
    await get(`/v1/tracks/${a}?limit=5000`, { headers: ta, expect: 400, invalid: true });
    await get(`/v1/tracks/${a}/relative/${b}`, { headers: ta, expect: 401 });
    await get(`/v1/tracks/${b}/relative/${a}`, { headers: { ...sb, 'x-peer-token': ta['x-track-token'] }, expect: 403 });
    await get(`/v1/tracks/${a}/events`, { headers: { 'x-track-token': 'trk_wrong' }, expect: 403 });
    await post(`/v1/tracks/${b}/close`, {}, own(tb, { expect: 200 }));
    await post(`/v1/tracks/${b}/close`, {}, own(sb, { expect: 403 }));
    // Prism's proxy takes every answer for JSON, so the event stream goes straight to the server.
    await get(`/v1/tracks/${b}/events`, { headers: tb, expect: 200, direct: true });
    await get(`/v1/tracks/${b}/events?token=${encodeURIComponent(tb['x-track-token'])}`, { expect: 200, direct: true });
    await post(`/v1/tracks/${b}/fixes`, { fixes: [fixOf(nowS, floor, 1, 1)] }, own(tb, { expect: 409 }));
    await post(`/v1/tracks/${b}/shares`, {}, own(tb, { expect: 409 }));
    await del(`/v1/tracks/${b}/shares/${share.json?.id ?? UNKNOWN}`, own(tb, { expect: 204 }));
    await del(`/v1/tracks/${b}/shares/${share.json?.id ?? UNKNOWN}`, own(tb, { expect: 404 }));
    await del(`/v1/tracks/${b}`, { auth: false, expect: 401 });
    await del(`/v1/tracks/${b}`, own(tb, { expect: 204 }));
    await get(`/v1/tracks/${b}`, { headers: tb, expect: 404 });
    await del(`/v1/tracks/${a}`, own(ta, { expect: 204 }));
  }
  await del(`/v1/floors/${floor2}/plan`, { expect: 204 });
  await del(`/v1/floors/${floor2}/plan`, { expect: 404 });

  // Plan images: a 4 × 2 PNG. Prism checks the requests and the JSON answers.
  const png = Buffer.from('iVBORw0KGgoAAAANSUhEUgAAAAQAAAACCAAAAABawyK/AAAADklEQVR4nGM4AQQMIAIAH0oGQVCurpAAAAAASUVORK5CYII=', 'base64');
  const image = `/v1/floors/${floor}/image`;
  const sendImage = (query, opts) => put(`${image}${query}`, undefined, { raw: png, contentType: 'image/png', ...opts });
  await get(image, { expect: 404 });
  await get(`${image}/placement`, { expect: 404 });
  await sendImage('?metres_per_pixel=0.5&origin_x=1&origin_y=-2&rotation_deg=15', { expect: 201, direct: true });
  await sendImage('?metres_per_pixel=0.25', { expect: 200, direct: true });
  const placement = await get(`${image}/placement`, { expect: 200 });
  await get(image, { expect: 200 });
  await get(image, { headers: { 'if-none-match': placement.json?.etag ?? '' }, expect: 304 });
  await patch(`${image}/placement`, { origin_x: 2.5, rotation_deg: -3 }, { expect: 200 });
  await patch(`${image}/placement`, { metres_per_pixel: 0 }, { expect: 422 });
  await patch(`${image}/placement`, { scale: 2 }, { expect: 422, invalid: true });
  await patch(`${image}/placement`, { origin_x: 1 }, { auth: false, expect: 401, invalid: true });
  await patch(`/v1/floors/${UNKNOWN}/image/placement`, { origin_x: 1 }, { expect: 404 });
  await sendImage('?metres_per_pixel=0.25', { contentType: 'image/jpeg', expect: 422, direct: true });
  await sendImage('?metres_per_pixel=0.25', { raw: 'not an image', expect: 422 });
  await sendImage('?metres_per_pixel=0.25', { contentType: 'image/gif', expect: 415, invalid: true });
  await sendImage('', { expect: 400, invalid: true });
  await sendImage('?metres_per_pixel=-1', { expect: 400, invalid: true });
  await sendImage('?metres_per_pixel=0.25&rotation_deg=400', { expect: 400, invalid: true });
  await sendImage('?metres_per_pixel=0.25', { auth: false, expect: 401, invalid: true });
  await put(`/v1/floors/${UNKNOWN}/image?metres_per_pixel=1`, undefined, { raw: png, contentType: 'image/png', expect: 404, direct: true });
  await get(`/v1/floors/${UNKNOWN}/image/placement`, { expect: 404 });
  await del(image, { expect: 204 });
  await del(image, { expect: 404 });
  // Without its plan the Lobby is an ordinary room again (deleted below).
  await del(`/v1/floors/${floor}/plan`, { expect: 204 });

  // Deletes, down the hierarchy and then the cascade
  await del(`/v1/rps/${rp2}`, { auth: false, expect: 401, invalid: true });
  await del(`/v1/rps/${rp2}`, { expect: 204 });
  await del(`/v1/rps/${rp2}`, { expect: 404 });
  await del(`/v1/transmitters/${tx}`, { expect: 204 });
  await del(`/v1/transmitters/${tx}`, { expect: 404 });
  await del(`/v1/pois/${poi}`, { expect: 204 });
  await del(`/v1/pois/${poi}`, { expect: 404 });
  await del(`/v1/rooms/${room}`, { expect: 204 });
  await del(`/v1/rooms/${room}`, { expect: 404 });
  await del(`/v1/radiomaps/${radiomap}`, { expect: 204 });
  await get(`/v1/rps/${rp1}`, { expect: 404 });
  await del(`/v1/radiomaps/${radiomap}`, { expect: 404 });
  await del(`/v1/floors/${floor}`, { expect: 204 });
  await del(`/v1/floors/${floor}`, { expect: 404 });
  await del(`/v1/buildings/${building}`, { expect: 204 });
  await get(`/v1/floors/${floor2}`, { expect: 404 });
  await get(`/v1/radiomaps/${radiomap2}`, { expect: 404 });
  await del(`/v1/buildings/${building}`, { expect: 404 });
  await del(`/v1/maps/${other}`, { expect: 204 });
  await del(`/v1/maps/${map}`, { expect: 204 });
  await del(`/v1/maps/${map}`, { expect: 404 });
}

// Follows local $refs of the bundled spec.
function deref(node) {
  for (let i = 0; node && node.$ref && i < 20; i++)
    node = node.$ref.slice(2).split('/').reduce((o, k) => o?.[k.replace(/~1/g, '/').replace(/~0/g, '~')], spec);
  return node;
}

// One HTTP/1.1 request without a Content-Length or body, straight to the server.
function rawRequest(method, path) {
  return new Promise((resolve) => {
    let data = '';
    const socket = connect(Number(server.port), server.hostname, () =>
      socket.write(`${method} ${path} HTTP/1.1\r\nHost: ${server.host}\r\nAuthorization: Bearer ${apiKey}\r\nConnection: close\r\n\r\n`),
    );
    socket.setTimeout(10000, () => socket.destroy(new Error('timed out')));
    socket.on('data', (d) => (data += d));
    socket.on('error', (e) => resolve({ error: e.message }));
    socket.on('close', () => {
      const [head, ...rest] = data.split('\r\n\r\n');
      const status = Number((head.match(/^HTTP\/1\.[01] (\d{3})/) || [])[1] || 0);
      const contentType = (head.match(/^content-type:\s*(.*)$/im) || [])[1] || '';
      resolve({ status, contentType, body: rest.join('\r\n\r\n') });
    });
  });
}

async function lengthRequired() {
  for (const op of operations) {
    if (!op.hasBody || skip.has(op.id)) continue;
    const path = op.template.replace(/\{[^}]+\}/g, '1');
    const what = `${op.method} ${path} without a Content-Length (straight to the server)`;
    direct++;
    const r = await rawRequest(op.method, path);
    if (r.error) {
      violations.push(`${what}: no answer (${r.error})`);
      continue;
    }
    if (op.bodyOptional ? r.status === 411 : r.status !== 411)
      violations.push(`${what}: expected ${op.bodyOptional ? 'no 411 (its body is optional)' : '411'}, got ${r.status} ${r.body.slice(0, 200)}`);
    const documented = deref(op.responses[String(r.status)]);
    if (!documented) {
      violations.push(`${what} -> ${r.status}: ${op.id} does not document status ${r.status}`);
      continue;
    }
    const schema = deref(documented.content?.['application/json']?.schema);
    const codes = deref(deref(schema?.properties?.error)?.properties?.code)?.enum;
    let body = null;
    try {
      body = JSON.parse(r.body);
    } catch {
      body = null;
    }
    if (!r.contentType.startsWith('application/json')) violations.push(`${what} -> ${r.status}: content type ${r.contentType}`);
    if (!body || typeof body.error?.code !== 'string' || typeof body.error?.message !== 'string')
      violations.push(`${what} -> ${r.status}: not an error body: ${r.body.slice(0, 200)}`);
    else if (codes && !codes.includes(body.error.code))
      violations.push(`${what} -> ${r.status}: error code ${body.error.code} is not one of ${codes.join(', ')}`);
  }
}

try {
  await run();
  await lengthRequired();
} catch (e) {
  violations.push(e.message);
}

// Coverage: every operation got a request and at least one successful answer.
const skippedOps = operations.filter((op) => skip.has(op.id));
for (const op of operations) {
  if (skip.has(op.id)) continue;
  if (op.seen.length === 0) violations.push(`${op.id} (${op.method} ${op.template}): no request`);
  else if (!op.seen.some((s) => s >= 200 && s < 300))
    violations.push(`${op.id} (${op.method} ${op.template}): no successful answer (got ${[...new Set(op.seen)].join(', ')})`);
}

// Each request must have reached the server (not been answered by Prism on its own): the
// server writes one JSON line with a "method" per request (its other lines are events).
if (serverLog) {
  await new Promise((r) => setTimeout(r, 300));
  const served = readFileSync(serverLog, 'utf8').split('\n').filter((l) => l.includes('"method"')).length;
  if (served > sent + direct || served < sent + direct - cut)
    violations.push(`the server logged ${served} requests of the ${sent} sent through Prism and ${direct} sent to it directly`);
}

for (const v of violations) console.log(`violation: ${v}`);
const covered = operations.length - skippedOps.length;
console.log(
  `contract: ${sent + direct} requests, ${violations.length} violations (${sent} through Prism, ${direct} straight to the server; ` +
    `${covered} of ${operations.length} operations exercised` +
    (skippedOps.length ? `; skipped by CONTRACT_SKIP: ${skippedOps.map((op) => op.id).join(', ')}, ${skipped} requests not sent` : '') +
    ')',
);
process.exit(violations.length ? 1 : 0);
