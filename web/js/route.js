// Search over the map's directory and routes between two places: a route's legs are drawn on
// their own floors (the one shown now, the others when their floor is chosen), its steps
// listed with a button to go to each leg's floor.
import { get, postRead } from './api.js';
import { ll } from './image_layer.js';
import { esc } from './floor_view.js';

const L = window.L;

export class RoutePanel {
  constructor(map, ui, viewer) {
    this.map = map;
    this.ui = ui;  // {form, input, results, from, to, go, clear, stepFree, summary, steps, pickFrom, pickTo}
    this.viewer = viewer;  // {mapId(), floorId(), floorName(id), showFloor(id)}
    this.ends = { from: null, to: null };  // {place, label}
    this.route = null;
    this.layer = L.layerGroup().addTo(map);
    this.picking = null;
    const report = (e) => viewer.status(`Error: ${e.message}`);
    ui.form.addEventListener('submit', (e) => { e.preventDefault(); this.search().catch(report); });
    ui.go.addEventListener('click', () => this.request().catch(report));
    ui.clear.addEventListener('click', () => this.clear());
    ui.pickFrom.addEventListener('click', () => this.startPick('from'));
    ui.pickTo.addEventListener('click', () => this.startPick('to'));
  }

  async search() {
    const q = this.ui.input.value.trim();
    this.ui.results.innerHTML = '';
    if (!q || !this.viewer.mapId()) return;
    const answer = await get(`/v1/maps/${this.viewer.mapId()}/search?q=${encodeURIComponent(q)}&limit=10`);
    if (!answer.hits.length) {
      this.ui.results.innerHTML = '<li>Nothing found.</li>';
      return;
    }
    for (const hit of answer.hits) {
      const li = document.createElement('li');
      const name = hit.name || (hit.tags && hit.tags[0]) || hit.kind;
      const where = `${this.viewer.floorName(hit.floor_id)}${hit.category ? `, ${hit.category}` : ''}`;
      li.innerHTML = `<span class="hit-name">${esc(name)}</span> <span class="hit-where">${esc(where)}</span>`;
      for (const end of ['from', 'to']) {
        const b = document.createElement('button');
        b.type = 'button';
        b.className = `hit-${end}`;
        b.textContent = end === 'from' ? 'From here' : 'To here';
        b.setAttribute('aria-label', `${b.textContent}: ${name}`);
        b.addEventListener('click', () => this.setEnd(end, hit.route_to, name));
        li.appendChild(b);
      }
      const show = document.createElement('button');
      show.type = 'button';
      show.textContent = 'Show';
      show.setAttribute('aria-label', `Show ${name} on the map`);
      show.addEventListener('click', () => this.viewer.showFloor(hit.floor_id)
        .then(() => this.map.setView(ll(hit.x, hit.y), Math.max(this.map.getZoom(), 3)))
        .catch((e) => this.viewer.status(`Error: ${e.message}`)));
      li.appendChild(show);
      this.ui.results.appendChild(li);
    }
  }

  setEnd(end, place, label) {
    this.ends[end] = { place, label };
    this.ui[end].textContent = label;
    this.ui.go.disabled = !(this.ends.from && this.ends.to);
    if (!this.ui.go.disabled) this.ui.go.focus();
  }

  startPick(end) {
    this.picking = end;
    this.map.getContainer().classList.add('picking');
    this.viewer.status(`Click the map to set the route's ${end === 'from' ? 'start' : 'end'}.`);
  }

  // A map click while picking: that point of the floor shown.
  takeClick(latlng) {
    if (!this.picking) return false;
    const end = this.picking;
    this.picking = null;
    this.map.getContainer().classList.remove('picking');
    const x = Math.round(latlng.lng * 100) / 100, y = Math.round(latlng.lat * 100) / 100;
    this.setEnd(end, { floor_id: this.viewer.floorId(), x, y }, `(${x}, ${y}) m on ${this.viewer.floorName(this.viewer.floorId())}`);
    this.viewer.status('');
    return true;
  }

  async request() {
    if (!(this.ends.from && this.ends.to)) return;
    const body = { from: this.ends.from.place, to: this.ends.to.place };
    if (this.ui.stepFree.checked) body.options = { step_free: true };
    try {
      this.route = await postRead(`/v1/maps/${this.viewer.mapId()}/route`, body);
    } catch (e) {
      this.route = null;
      this.layer.clearLayers();
      this.ui.steps.innerHTML = '';
      this.ui.summary.textContent = `No route: ${e.message}`;
      return;
    }
    const r = this.route;
    // The time as `locus route` says it: seconds under a minute and a half, else minutes to a tenth.
    const time = r.time_s < 90 ? `${Math.round(r.time_s)} s` : `${(r.time_s / 60).toFixed(1)} min`;
    this.ui.summary.innerHTML = `<p id="route-length" data-length-m="${r.length_m}">${r.length_m.toFixed(1)} m, about ${time}`
      + `${r.legs.length > 1 ? `, ${r.legs.length} floors` : ''}</p>`;
    this.ui.steps.innerHTML = '';
    let leg = 0;
    const legButton = (i) => {
      const l = r.legs[i];
      const b = document.createElement('button');
      b.type = 'button';
      b.className = 'leg-floor';
      b.textContent = `${this.viewer.floorName(l.floor_id)}: ${l.length_m.toFixed(0)} m`;
      b.addEventListener('click', () => this.viewer.showFloor(l.floor_id).catch((e) => this.viewer.status(`Error: ${e.message}`)));
      const li = document.createElement('li');
      li.className = 'leg';
      li.appendChild(b);
      this.ui.steps.appendChild(li);
    };
    legButton(leg);
    let n = 0;
    for (const s of r.steps) {
      const li = document.createElement('li');
      li.value = ++n;  // the floors' buttons are items too; the steps count on their own
      li.textContent = s.text;
      li.className = `step step-${s.kind}`;
      this.ui.steps.appendChild(li);
      if (s.kind === 'take_connector' && leg + 1 < r.legs.length) legButton(++leg);
    }
    if (r.from.floor_id !== this.viewer.floorId()) await this.viewer.showFloor(r.from.floor_id);
    else this.draw();
    const here = this.polylines.length ? L.featureGroup(this.polylines).getBounds() : null;
    if (here && here.isValid()) this.map.fitBounds(here.pad(0.3), { maxZoom: this.map.getZoom() });
  }

  // Draws the legs on the floor shown; called again on every floor change.
  draw() {
    this.layer.clearLayers();
    this.polylines = [];
    if (!this.route) return;
    const floor = this.viewer.floorId();
    for (const leg of this.route.legs) {
      if (leg.floor_id !== floor) continue;
      const line = L.polyline(leg.path.map(([x, y]) => ll(x, y)), { className: 'route-line', weight: 5, interactive: false });
      this.layer.addLayer(line);
      this.polylines.push(line);
    }
    const mark = (end, cls, text) => {
      if (end.floor_id === floor) this.layer.addLayer(L.circleMarker(ll(end.x, end.y), { radius: 7, className: cls }).bindTooltip(text));
    };
    mark(this.route.from, 'route-from', 'Start');
    mark(this.route.to, 'route-to', 'Destination');
  }

  clear() {
    this.route = null;
    this.ends = { from: null, to: null };
    this.ui.from.textContent = 'not set';
    this.ui.to.textContent = 'not set';
    this.ui.go.disabled = true;
    this.ui.summary.textContent = '';
    this.ui.steps.innerHTML = '';
    this.layer.clearLayers();
    this.polylines = [];
  }
}
