// The predicted-error layer: each RP of the shown floor coloured by its held-out error with the
// radio map's current settings (GET /v1/radiomaps/{id}/quality): where the map's own RPs cannot
// place one another, a phone will be placed badly too. Green to red over 0 m to the worst
// error (at least 10 m, so a good map stays green); a legend says the scale.
import { get } from './api.js';
import { ll } from './image_layer.js';
import { esc } from './floor_view.js';

const L = window.L;
const SCALE_MIN_M = 10;

// t in [0, 1]: green (small error), amber, red (large).
function errorCss(t) {
  const u = Math.min(1, Math.max(0, t));
  const stops = [[26, 127, 55], [191, 135, 0], [207, 34, 46]];
  const i = u < 0.5 ? 0 : 1;
  const f = u < 0.5 ? u * 2 : (u - 0.5) * 2;
  return `rgb(${stops[i].map((c, k) => Math.round(c + (stops[i + 1][k] - c) * f)).join(',')})`;
}

export class QualityLayer {
  constructor(map, { toggle, summary }) {
    this.map = map;
    this.toggle = toggle;
    this.summary = summary;
    this.group = L.layerGroup().addTo(map);
    this.legend = null;
    this.shown = [];  // [{id, name, error_m, colour}] for tests: read only
    this.ticket = 0;
  }

  clear() {
    this.group.clearLayers();
    if (this.legend) this.map.removeControl(this.legend);
    this.legend = null;
    this.shown = [];
    this.summary.textContent = '';
  }

  // Draws (or removes, when the toggle is off) the layer for the floor and radio map shown.
  async show(floorId, radiomapId) {
    const ticket = ++this.ticket;
    this.clear();
    if (!this.toggle.checked || !radiomapId) return;
    this.summary.textContent = 'Localizing each RP against the others…';
    const q = await get(`/v1/radiomaps/${radiomapId}/quality`);
    if (ticket !== this.ticket) return;  // another floor or radio map was chosen meanwhile
    const here = q.rps.filter((rp) => rp.floor_id === floorId && rp.error_m !== null);
    const worst = Math.max(SCALE_MIN_M, ...here.map((rp) => rp.error_m));
    for (const rp of here) {
      const colour = errorCss(rp.error_m / worst);
      L.circleMarker(ll(rp.x, rp.y), { radius: 9, className: 'quality-rp', color: colour, fillColor: colour, fillOpacity: 0.55, weight: 2 })
        .bindTooltip(esc(`${rp.name}: ${rp.error_m.toFixed(1)} m${rp.floor_ok ? '' : ', wrong floor'}`), { direction: 'top', className: 'label' })
        .addTo(this.group);
      this.shown.push({ id: rp.id, name: rp.name, error_m: rp.error_m, colour });
    }
    this.legend = legendControl(worst);
    this.legend.addTo(this.map);
    this.summary.textContent = `Predicted error with the radio map's ${q.settings.source} settings: mean ${q.mean_error_m.toFixed(1)} m`
      + ` over ${q.queries} RPs (${q.folds}-fold${q.subsampled ? ', a sample' : ''}).`;
  }
}

function legendControl(worst) {
  const c = L.control({ position: 'bottomleft' });
  c.onAdd = () => {
    const div = L.DomUtil.create('div', 'legend quality-legend');
    div.setAttribute('role', 'img');
    div.setAttribute('aria-label', `Predicted error: green 0 m to red ${worst.toFixed(0)} m`);
    const stops = [0, 0.5, 1].map((t) => `${errorCss(t)} ${t * 100}%`).join(',');
    div.innerHTML = '<div class="legend-title">Predicted error, m</div>'
      + `<div class="legend-bar" style="background: linear-gradient(to right, ${stops})"></div>`
      + `<div class="legend-scale"><span>0</span><span>${(worst / 2).toFixed(0)}</span><span>${worst.toFixed(0)}</span></div>`;
    return div;
  };
  return c;
}
