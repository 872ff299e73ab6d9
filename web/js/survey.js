// Planning a survey on the floor shown: planned RPs placed by clicking (dragged to move, clicked
// to remove), or a grid filled as `locus survey plan --cell C` does (cell centres of
// ceil(w / C) x ceil(h / C) cells, only those inside a room when the floor has rooms, named
// gRRR_CCC); exported in that command's JSON shape, or created in the radio map (a write: it
// needs the API key).
import { apiKey, postWrite } from './api.js';
import { ll } from './image_layer.js';

const L = window.L;

const plannedIcon = L.divIcon({ className: 'planned-marker', iconSize: [14, 14] });

export class SurveyPlanner {
  constructor(map, ui, viewer) {
    this.map = map;
    this.ui = ui;  // {mode, cell, fill, exportBtn, create, clear, summary}
    this.viewer = viewer;  // {floor(), rooms(), radiomapId(), status(text), askKey()}
    this.points = [];  // {name, x, y, marker}
    this.layer = L.layerGroup().addTo(map);
    this.grid = L.layerGroup().addTo(map);
    this.manual = 0;
    ui.fill.addEventListener('click', () => this.fillGrid());
    ui.exportBtn.addEventListener('click', () => this.download());
    ui.create.addEventListener('click', () => this.create().catch((e) => viewer.status(`Error: ${e.message}`)));
    ui.clear.addEventListener('click', () => this.reset());
    ui.mode.addEventListener('change', () => this.drawGrid());
    ui.cell.addEventListener('change', () => this.drawGrid());
  }

  cell() {
    const v = Number(this.ui.cell.value);
    return Number.isFinite(v) && v >= 0.5 ? v : 2;
  }

  // The survey command's grid as light lines while planning.
  drawGrid() {
    this.grid.clearLayers();
    const floor = this.viewer.floor();
    if (!this.ui.mode.checked || !floor) return;
    const { cols, rows, dx, dy } = this.gridOf(floor);
    if (cols * rows > 20000) return;  // too fine to draw usefully
    for (let c = 0; c <= cols; ++c) this.grid.addLayer(L.polyline([ll(c * dx, 0), ll(c * dx, floor.height)], { className: 'survey-grid', weight: 1, interactive: false }));
    for (let r = 0; r <= rows; ++r) this.grid.addLayer(L.polyline([ll(0, r * dy), ll(floor.width, r * dy)], { className: 'survey-grid', weight: 1, interactive: false }));
  }

  gridOf(floor) {
    const cols = Math.ceil(floor.width / this.cell()), rows = Math.ceil(floor.height / this.cell());
    return { cols, rows, dx: floor.width / cols, dy: floor.height / rows };
  }

  // A map click in survey mode adds a planned RP there.
  takeClick(latlng) {
    if (!this.ui.mode.checked) return false;
    const x = Math.round(latlng.lng * 100) / 100, y = Math.round(latlng.lat * 100) / 100;
    this.add(`p${String(++this.manual).padStart(3, '0')}`, x, y);
    this.update();
    return true;
  }

  add(name, x, y) {
    if (this.points.some((p) => p.name === name)) return;
    const marker = L.marker(ll(x, y), { icon: plannedIcon, draggable: true, title: `Planned RP ${name} (click to remove)`, keyboard: true });
    const point = { name, x, y, marker };
    marker.on('dragend', () => {
      const p = marker.getLatLng();
      point.x = Math.round(p.lng * 100) / 100;
      point.y = Math.round(p.lat * 100) / 100;
    });
    const remove = () => {
      this.layer.removeLayer(marker);
      this.points = this.points.filter((q) => q !== point);
      this.update();
    };
    marker.on('click', remove);
    marker.on('keypress', (e) => { if (e.originalEvent.key === 'Enter' || e.originalEvent.key === 'Delete') remove(); });
    marker.addTo(this.layer);
    this.points.push(point);
  }

  fillGrid() {
    const floor = this.viewer.floor();
    if (!floor) return;
    const rooms = this.viewer.rooms();
    const { cols, rows, dx, dy } = this.gridOf(floor);
    if (cols * rows > 20000) {
      this.viewer.status('That cell makes more than 20,000 grid points: use a larger cell.');
      return;
    }
    const inside = (x, y) => !rooms.length || rooms.some((room) => room.rects.some((r) => x >= r.xmin && x <= r.xmax && y >= r.ymin && y <= r.ymax));
    for (let r = 0; r < rows; ++r) {
      for (let c = 0; c < cols; ++c) {
        const x = (c + 0.5) * dx, y = (r + 0.5) * dy;
        if (inside(x, y)) this.add(`g${String(r).padStart(3, '0')}_${String(c).padStart(3, '0')}`, x, y);
      }
    }
    this.update();
  }

  update() {
    this.ui.summary.textContent = this.points.length ? `${this.points.length} planned RPs on this floor.` : 'No planned RPs.';
  }

  reset() {
    this.layer.clearLayers();
    this.points = [];
    this.manual = 0;
    this.update();
  }

  // `locus survey plan`'s output shape: the same points a surveyor would get from the CLI.
  planDocument() {
    const floor = this.viewer.floor();
    const { cols, rows } = this.gridOf(floor);
    return {
      floor_id: floor.id, width: floor.width, height: floor.height, cell: this.cell(),
      required_points: Math.ceil(floor.width * floor.height / (this.cell() * this.cell()) - 1e-9),
      columns: cols, rows, proposed: this.points.length,
      points: this.points.map(({ name, x, y }) => ({ name, x, y })),
    };
  }

  download() {
    if (!this.viewer.floor() || !this.points.length) {
      this.viewer.status('Nothing to export: place planned RPs first.');
      return;
    }
    const blob = new Blob([JSON.stringify(this.planDocument(), null, 1)], { type: 'application/json' });
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `survey-plan-floor-${this.viewer.floor().id}.json`;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  }

  // Creates each planned RP in the floor's radio map, skipping names it already has.
  async create() {
    const rm = this.viewer.radiomapId();
    if (!rm) {
      this.viewer.status('This floor has no radio map to add RPs to.');
      return;
    }
    const existing = new Set(this.viewer.rpNames());
    let created = 0, skipped = 0;
    try {
      for (const p of this.points) {
        if (existing.has(p.name)) { ++skipped; continue; }
        await postWrite(`/v1/radiomaps/${rm}/rps`, { name: p.name, x: p.x, y: p.y });
        ++created;
      }
    } catch (e) {
      this.viewer.status(`Stopped after ${created} RPs: ${e.message}`);
      this.viewer.reloadRadio().catch(() => {});
      if (e.status === 401) this.viewer.askKey(apiKey() ? 'The server refused the key: enter the right API key, then Create RPs again.'
        : 'Creating RPs is an edit and this server asks for its API key: enter it, Save, then Create RPs again.');
      return;
    }
    this.viewer.status(`Created ${created} RPs (${skipped} already there).`);
    this.reset();
    await this.viewer.reloadRadio();
  }
}
