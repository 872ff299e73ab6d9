// The viewer: map → building → floor pickers, the floor drawn in metres (L.CRS.Simple), and the
// panels (search and route, RP details, radio-map quality, survey plan, API key).
import { get, listAll, imagePlacement, planOf, apiKey, setApiKey } from './api.js';
import { floorLayers } from './floor_view.js';
import { RadioLayer } from './radio.js';
import { RoutePanel } from './route.js';
import { SurveyPlanner } from './survey.js';
import { followFloor } from './live.js';
import { QualityLayer } from './quality.js';
import { installCreatePanel } from './create.js';

const L = window.L;
const $ = (id) => document.getElementById(id);

const state = { maps: [], buildings: [], floors: [], floor: null, rooms: [], radiomaps: [], radiomapId: null, mapId: null };
const floorNames = new Map();  // floor id → "Building / Floor" for every floor of the map
let base = null;
let stopLive = () => {};

const map = L.map('map', { crs: L.CRS.Simple, minZoom: -3, maxZoom: 6, zoomSnap: 0.25, attributionControl: false, keyboard: true });
L.control.scale({ imperial: false, metric: true, position: 'bottomright' }).addTo(map);
const liveLayer = L.layerGroup().addTo(map);

function status(text) { $('status').textContent = text; }
// Why the live layer shows nothing (the positions stream refused), beside the status line.
function liveNote(text) { $('live-status').textContent = text; }

function fill(select, items, label) {
  select.innerHTML = '';
  for (const it of items) {
    const o = document.createElement('option');
    o.value = it.id;
    o.textContent = label(it);
    select.appendChild(o);
  }
  select.disabled = items.length === 0;
}

const quality = new QualityLayer(map, { toggle: $('quality-toggle'), summary: $('quality-summary') });
const radio = new RadioLayer(map, { details: $('rp-details'), apSelect: $('ap-select'), summary: $('radio-summary'), gapsToggle: $('gaps-toggle'), gapMetres: $('gap-metres') });

const viewer = {
  mapId: () => state.mapId,
  buildingId: () => Number($('building-select').value) || null,
  floorId: () => (state.floor ? state.floor.id : null),
  floor: () => state.floor,
  rooms: () => state.rooms,
  radiomapId: () => state.radiomapId,
  rpNames: () => radio.rps.map((rp) => rp.name),
  floorName: (id) => floorNames.get(id) || `floor ${id}`,
  showFloor: (id) => showFloorById(id),
  status,
  askKey(message) {
    status(message);
    $('api-key').focus();
  },
  reloadRadio: () => radio.show(state.floor, state.radiomapId),
};

const route = new RoutePanel(map, {
  form: $('search-form'), input: $('search-input'), results: $('search-results'), from: $('route-from'), to: $('route-to'),
  go: $('route-go'), clear: $('route-clear'), stepFree: $('step-free'), summary: $('route-summary'), steps: $('route-steps'),
  pickFrom: $('pick-from'), pickTo: $('pick-to'),
}, viewer);
const survey = new SurveyPlanner(map, {
  mode: $('survey-mode'), cell: $('grid-cell'), fill: $('grid-fill'), exportBtn: $('survey-export'), create: $('survey-create'),
  clear: $('survey-clear'), summary: $('survey-summary'),
}, viewer);

map.on('click', (e) => { if (!route.takeClick(e.latlng)) survey.takeClick(e.latlng); });

// The address names the map and floor shown (`#map=1&floor=2`), so a link opens that floor.
function linked() {
  const p = new URLSearchParams(location.hash.slice(1));
  const num = (k) => (/^[1-9][0-9]*$/.test(p.get(k) || '') ? Number(p.get(k)) : null);
  return { mapId: num('map'), floorId: num('floor') };
}

async function loadMaps() {
  state.maps = await listAll('/v1/maps');
  fill($('map-select'), state.maps, (m) => m.name);
  if (!state.maps.length) {
    status('The server has no map yet.');
    return;
  }
  const link = linked();
  const known = state.maps.some((m) => m.id === link.mapId);
  await selectMap(known ? link.mapId : state.maps[0].id, known ? link.floorId : null);
}

async function selectMap(id, floorId = null) {
  state.mapId = Number(id);
  $('map-select').value = String(id);
  state.buildings = await listAll(`/v1/maps/${id}/buildings`);
  fill($('building-select'), state.buildings, (b) => b.name);
  // Every floor's name, for search hits and route legs on other buildings' floors.
  floorNames.clear();
  const perBuilding = await Promise.all(state.buildings.map((b) => listAll(`/v1/buildings/${b.id}/floors`)));
  perBuilding.forEach((floors, i) => {
    for (const f of floors) floorNames.set(f.id, `${state.buildings[i].name} / ${f.name}`);
  });
  route.clear();
  // The linked floor's building, else the first.
  const at = Math.max(0, perBuilding.findIndex((floors) => floors.some((f) => f.id === floorId)));
  const linkedFloor = perBuilding[at]?.some((f) => f.id === floorId) ? floorId : undefined;
  if (state.buildings.length) await selectBuilding(state.buildings[at].id, linkedFloor, perBuilding[at]);
  else fill($('floor-select'), [], () => '');
}

async function selectBuilding(id, floorId, floors) {
  $('building-select').value = String(id);
  state.floors = (floors || await listAll(`/v1/buildings/${id}/floors`)).slice().sort((a, b) => a.level - b.level);
  fill($('floor-select'), state.floors, (f) => `${f.name} (level ${f.level})`);
  const pick = floorId ?? (state.floors.find((f) => f.level === 0) || state.floors[0] || {}).id;
  if (pick !== undefined) await selectFloor(pick);
}

async function showFloorById(id) {
  if (state.floor && state.floor.id === id) return;
  const floor = await get(`/v1/floors/${id}`);
  if (floor.building_id !== Number($('building-select').value)) await selectBuilding(floor.building_id, id);
  else await selectFloor(id);
}

async function selectFloor(id) {
  const started = performance.now();
  document.body.dataset.floorReady = 'false';
  $('floor-select').value = String(id);
  const floor = state.floors.find((f) => f.id === Number(id)) || await get(`/v1/floors/${id}`);
  state.floor = floor;
  // Everything at once; the radio map's export as soon as its id is known.
  const radiomapsP = listAll(`/v1/floors/${id}/radiomaps`);
  const exportP = radiomapsP.then((rms) => (rms.length ? get(`/v1/radiomaps/${rms[0].id}/export`) : null));
  const [rooms, pois, plan, placement, radiomaps, doc] = await Promise.all([
    listAll(`/v1/floors/${id}/rooms`), listAll(`/v1/floors/${id}/pois`), planOf(id), imagePlacement(id), radiomapsP, exportP,
  ]);
  if (state.floor !== floor) return;  // another floor was chosen meanwhile
  history.replaceState(null, '', `#map=${state.mapId}&floor=${floor.id}`);
  state.rooms = rooms;
  state.radiomaps = radiomaps;
  if (base) map.removeLayer(base);
  const drawn = floorLayers(floor, rooms, pois, plan, placement);
  base = drawn.group.addTo(map);
  map.fitBounds(drawn.bounds.pad(0.05));
  fill($('radiomap-select'), radiomaps, (r) => r.name);
  state.radiomapId = radiomaps.length ? radiomaps[0].id : null;
  $('rp-details').innerHTML = '<p>Click a dot (or focus it and press Enter) to see its access points.</p>';
  await radio.show(floor, state.radiomapId, doc);
  if (state.floor !== floor) return;  // another floor was chosen while the radio map loaded
  applyRadioLayers();
  route.draw();
  survey.reset();
  survey.drawGrid();
  stopLive();
  stopLive = followFloor({ mapId: state.mapId, floorId: floor.id, layer: liveLayer, note: liveNote });
  // When the floor became visible, for the first-paint measurement (scripts/viewer_first_paint.py).
  requestAnimationFrame(() => {
    window.locusViewer.lastFloorMs = performance.now() - started;
    document.body.dataset.floorReady = 'true';
  });
  status(`${viewer.floorName(floor.id)}: ${metres(floor.width)} m × ${metres(floor.height)} m${placement ? ', plan image' : ''}${plan ? ', plan' : ''}.`);
}

// Sizes for people: 105.29699999839067 reads 105.3.
const metres = (v) => Number(v.toFixed(2));

function applyRadioLayers() {
  radio.showHeat($('ap-select').value);
  radio.showGaps($('gaps-toggle').checked);
  showQuality();
}

function showQuality() {
  quality.show(state.floor ? state.floor.id : null, state.radiomapId).catch((e) => {
    $('quality-summary').textContent = `Error: ${e.message}`;
  });
}

function guard(fn) {
  return (...args) => Promise.resolve(fn(...args)).catch((e) => status(`Error: ${e.message}`));
}

$('map-select').addEventListener('change', guard((e) => selectMap(e.target.value)));
$('building-select').addEventListener('change', guard((e) => selectBuilding(Number(e.target.value))));
$('floor-select').addEventListener('change', guard((e) => selectFloor(Number(e.target.value))));
$('radiomap-select').addEventListener('change', guard(async (e) => {
  state.radiomapId = Number(e.target.value);
  await radio.show(state.floor, state.radiomapId);
  applyRadioLayers();
}));
$('ap-select').addEventListener('change', () => radio.showHeat($('ap-select').value));
$('gaps-toggle').addEventListener('change', () => radio.showGaps($('gaps-toggle').checked));
$('gap-metres').addEventListener('change', applyRadioLayers);
$('quality-toggle').addEventListener('change', showQuality);
$('api-key').value = apiKey();
$('key-form').addEventListener('submit', (e) => {
  e.preventDefault();
  setApiKey($('api-key').value.trim());
  status($('api-key').value.trim() ? 'Key saved in this browser.' : 'Key removed.');
  // Positions need the key on a keyed server: follow the floor again with it.
  if (state.floor) {
    stopLive();
    stopLive = followFloor({ mapId: state.mapId, floorId: state.floor.id, layer: liveLayer, note: liveNote });
  }
});
$('panel-toggle').addEventListener('click', () => {
  const open = document.body.classList.toggle('panel-closed') === false;
  $('panel-toggle').setAttribute('aria-expanded', String(open));
  setTimeout(() => map.invalidateSize(), 0);
});

// After a create, the pickers are read again and the new item chosen.
installCreatePanel(viewer, {
  mapCreated: guard(async (id) => {
    state.maps = await listAll('/v1/maps');
    fill($('map-select'), state.maps, (m) => m.name);
    await selectMap(id);
  }),
  buildingCreated: guard(async (id) => {
    await selectMap(state.mapId);
    await selectBuilding(id);
  }),
  floorCreated: guard(async (buildingId, floorId) => {
    await selectMap(state.mapId);
    await selectBuilding(buildingId, floorId);
  }),
});

// A handle for tests and the first-paint script: the layers, read-only use.
window.locusViewer = { map, radio, route, survey, quality, state, liveLayer, lastFloorMs: null };

// A link pasted into this page's address bar: show what it names.
window.addEventListener('hashchange', guard(async () => {
  const link = linked();
  if (link.floorId && link.floorId !== viewer.floorId()) {
    if (link.mapId && link.mapId !== state.mapId && state.maps.some((m) => m.id === link.mapId)) await selectMap(link.mapId, link.floorId);
    else await showFloorById(link.floorId);
  }
}));

guard(loadMaps)();
