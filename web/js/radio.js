// A radio map on the floor: every RP a dot (a focusable marker: click or Enter shows its APs),
// the heat map of one AP's stored mean, and the gaps farther than N m from any RP.
import { get, listAll } from './api.js';
import { ll } from './image_layer.js';
import { esc } from './floor_view.js';
import { idwRaster, gapRaster, rasterUrl, rampCss } from './heat.js';

const L = window.L;

const rpIcon = L.divIcon({ className: 'rp-marker', iconSize: [12, 12] });

export class RadioLayer {
  constructor(map, ui) {
    this.map = map;
    this.ui = ui;  // {details, apSelect, summary, gapsToggle, gapMetres}
    this.group = L.layerGroup().addTo(map);
    this.heat = null;
    this.gaps = null;
    this.legend = null;
    this.rps = [];       // [{id, name, x, y, scans, measurements}]
    this.markers = [];
    this.floor = null;
  }

  clear() {
    this.group.clearLayers();
    this.dropRaster('heat');
    this.dropRaster('gaps');
    this.rps = [];
    this.markers = [];
  }

  // Draws the radio map's RPs from its export (one request: positions and measurements); the
  // RP ids, needed only to open one, come from the list meanwhile. `doc`: the export when the
  // caller already asked for it.
  async show(floor, radiomapId, doc) {
    this.clear();
    this.floor = floor;
    this.radiomapId = radiomapId;
    if (!radiomapId) {
      this.ui.summary.textContent = 'This floor has no radio map.';
      this.fillApSelect();
      return;
    }
    this.ids = listAll(`/v1/radiomaps/${radiomapId}/rps`).then((list) => new Map(list.map((rp) => [rp.name, rp.id])));
    this.ids.catch(() => {});  // reported when an RP is opened
    if (!doc) doc = await get(`/v1/radiomaps/${radiomapId}/export`);
    this.rps = doc.rps.map((rp) => ({ ...rp, measurements: rp.measurements || [] }));
    for (const rp of this.rps) {
      const m = L.marker(ll(rp.x, rp.y), { icon: rpIcon, title: `RP ${rp.name}`, alt: `RP ${rp.name}`, keyboard: true, riseOnHover: true });
      const open = () => this.select(rp, m).catch((e) => { this.ui.details.textContent = `Error: ${e.message}`; });
      m.on('click', open);
      // Leaflet turns Enter on a focused marker into a popup only: the table is this RP's popup.
      m.on('keypress', (e) => { if (e.originalEvent.key === 'Enter' || e.originalEvent.key === ' ') open(); });
      m.addTo(this.group);
      this.markers.push(m);
    }
    this.fillApSelect();
    this.updateSummary();
  }

  apsOf() {
    const aps = new Map();
    for (const rp of this.rps) for (const m of rp.measurements) aps.set(m.bssid, (aps.get(m.bssid) || 0) + 1);
    return [...aps.entries()].sort((a, b) => b[1] - a[1] || a[0].localeCompare(b[0]));
  }

  fillApSelect() {
    const sel = this.ui.apSelect;
    const keep = sel.value;
    sel.innerHTML = '<option value="">none</option>';
    for (const [bssid, n] of this.apsOf()) {
      const o = document.createElement('option');
      o.value = bssid;
      o.textContent = `${bssid} (${n} RPs)`;
      sel.appendChild(o);
    }
    sel.value = [...sel.options].some((o) => o.value === keep) ? keep : '';
  }

  updateSummary() {
    const n = this.rps.length;
    const area = this.floor ? this.floor.width * this.floor.height : 0;
    let text = `${n} RPs, ${area > 0 ? (n / area * 100).toFixed(1) : '0'} per 100 m².`;
    if (this.gapShare !== undefined && this.gaps) text += ` ${(this.gapShare * 100).toFixed(0)} % of the floor is farther than ${this.gapMetres()} m from any RP.`;
    this.ui.summary.textContent = text;
  }

  async select(rp, marker) {
    for (const m of this.markers) L.DomUtil.removeClass(m.getElement(), 'selected');
    if (marker.getElement()) L.DomUtil.addClass(marker.getElement(), 'selected');
    const id = (await this.ids).get(rp.name);
    if (id === undefined) throw new Error(`RP ${rp.name} is no longer in the radio map`);
    const fresh = await get(`/v1/rps/${id}`);  // the stored state now, not the page's copy
    const rows = fresh.measurements
      .slice().sort((a, b) => b.mean - a.mean)
      .map((m) => `<tr><th scope="row">${esc(m.bssid)}</th><td>${esc(m.type || 'wifi')}</td><td>${m.mean.toFixed(1)}</td>`
        + `<td>${m.variance.toFixed(2)}</td><td>${m.count}</td></tr>`).join('');
    this.ui.details.innerHTML =
      `<p><strong>${esc(fresh.name)}</strong> at (${fresh.x.toFixed(2)}, ${fresh.y.toFixed(2)}) m, ${fresh.scans} scans,`
      + ` ${fresh.measurements.length} APs</p>`
      + `<p>Last upload: ${lastUpload(fresh.last_upload_at)}</p>`
      + `<div class="table-wrap"><table id="rp-table"><caption>Per access point, strongest first</caption>`
      + '<thead><tr><th scope="col">AP</th><th scope="col">Type</th><th scope="col">Mean dBm</th>'
      + `<th scope="col">Variance</th><th scope="col">Count</th></tr></thead><tbody>${rows}</tbody></table></div>`;
    this.ui.details.dispatchEvent(new CustomEvent('rp-shown', { bubbles: true, detail: fresh }));
  }

  dropRaster(name) {
    if (this[name]) this.map.removeLayer(this[name]);
    this[name] = null;
    if (name === 'heat' && this.legend) {
      this.map.removeControl(this.legend);
      this.legend = null;
    }
  }

  gapMetres() {
    const v = Number(this.ui.gapMetres.value);
    return Number.isFinite(v) && v > 0 ? v : 4;
  }

  floorBounds() {
    return L.latLngBounds(ll(0, 0), ll(this.floor.width, this.floor.height));
  }

  showHeat(bssid) {
    this.dropRaster('heat');
    if (!bssid || !this.floor) return;
    const samples = [];
    for (const rp of this.rps) {
      const m = rp.measurements.find((q) => q.bssid === bssid);
      if (m) samples.push({ x: rp.x, y: rp.y, v: m.mean });
    }
    if (!samples.length) return;
    let lo = Math.min(...samples.map((s) => s.v)), hi = Math.max(...samples.map((s) => s.v));
    if (hi - lo < 1) { lo -= 0.5; hi += 0.5; }
    const raster = idwRaster(samples, this.floor.width, this.floor.height, Math.max(2 * this.gapMetres(), 5), lo, hi);
    this.heat = L.imageOverlay(rasterUrl(raster), this.floorBounds(), { opacity: 0.65, className: 'heat-layer', alt: `Heat map of ${bssid}` });
    this.heat.addTo(this.map).bringToBack();
    this.legend = legendControl(bssid, lo, hi);
    this.legend.addTo(this.map);
  }

  showGaps(on) {
    this.dropRaster('gaps');
    if (!on || !this.floor) {
      this.updateSummary();
      return;
    }
    const raster = gapRaster(this.rps, this.floor.width, this.floor.height, this.gapMetres());
    this.gapShare = raster.share;
    this.gaps = L.imageOverlay(rasterUrl(raster), this.floorBounds(), { className: 'gaps-layer', alt: 'Gaps in the radio map' });
    this.gaps.addTo(this.map);
    this.updateSummary();
  }
}

// The server's UTC time in the reader's local time; null (imported, generated or created
// empty) is "never". The <time> keeps the exact value for tools and tests.
function lastUpload(iso) {
  if (!iso) return '<time id="rp-last-upload">never</time>';
  return `<time id="rp-last-upload" datetime="${esc(iso)}">${esc(new Date(iso).toLocaleString())}</time>`;
}

function legendControl(bssid, lo, hi) {
  const c = L.control({ position: 'bottomleft' });
  c.onAdd = () => {
    const div = L.DomUtil.create('div', 'legend');
    div.setAttribute('role', 'img');
    div.setAttribute('aria-label', `Mean RSS of ${bssid}: ${lo.toFixed(0)} to ${hi.toFixed(0)} dBm`);
    const stops = [0, 0.25, 0.5, 0.75, 1].map((t) => `${rampCss(t)} ${t * 100}%`).join(',');
    div.innerHTML = `<div class="legend-title">${esc(bssid)}, mean dBm</div>`
      + `<div class="legend-bar" style="background: linear-gradient(to right, ${stops})"></div>`
      + `<div class="legend-scale"><span>${lo.toFixed(0)}</span><span>${((lo + hi) / 2).toFixed(0)}</span><span>${hi.toFixed(0)}</span></div>`;
    return div;
  };
  return c;
}
