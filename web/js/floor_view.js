// One floor's base map: its outline, the plan image when it has one, the plan's spaces, walls,
// doors and connectors, else the API rooms; room and POI names as labels. Coordinates are floor
// metres: x east along the floor's width, y along its height, L.CRS.Simple's lng and lat.
import { ll, planImageLayer } from './image_layer.js';

const L = window.L;

function esc(s) {
  return String(s).replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' })[c]);
}
export { esc };

function label(layer, text, cls) {
  if (text) layer.bindTooltip(esc(text), { permanent: true, direction: 'center', className: `label ${cls}` });
}

// GeoJSON [x, y] to Leaflet (lat = y, lng = x): the plan is in metres, not degrees.
const coordsToLatLng = (c) => L.latLng(c[1], c[0]);

const POI_GLYPH = { exit: '⇥', stairs: '▤', elevator: '⇅', escalator: '⇗', ramp: '⟋', extinguisher: '!', toilet: 'WC' };

export function poiMarker(poi) {
  const glyph = POI_GLYPH[poi.kind] || '•';
  const icon = L.divIcon({ className: 'poi-icon', html: `<span aria-hidden="true">${esc(glyph)}</span>`, iconSize: [18, 18] });
  const m = L.marker(ll(poi.x, poi.y), { icon, title: `${poi.name}${poi.kind ? ` (${poi.kind})` : ''}`, alt: poi.name, keyboard: true });
  m.bindTooltip(esc(poi.name), { direction: 'top', offset: [0, -8], className: 'label poi' });
  return m;
}

// floor: the API floor; rooms, pois: its lists; plan: GeoJSON or null; placement: the image's
// or null. Returns a layer group and the bounds to fit.
export function floorLayers(floor, rooms, pois, plan, placement) {
  const group = L.layerGroup();
  const outline = L.rectangle(L.latLngBounds(ll(0, 0), ll(floor.width, floor.height)),
    { className: 'floor-outline', interactive: false, fill: !placement, fillColor: '#d0d7de', fillOpacity: 0.3 });
  group.addLayer(outline);
  let bounds = outline.getBounds();
  if (placement) {
    group.addLayer(planImageLayer(floor.id, placement));
    for (const [x, y] of placement.corners) bounds = bounds.extend(ll(x, y));
  }
  const labelled = new Set();
  if (plan && plan.features && plan.features.length) {
    const geo = L.geoJSON(plan, {
      coordsToLatLng,
      interactive: false,
      style: (f) => {
        const kind = f.properties.feature;
        if (kind === 'wall') return { className: 'plan-wall', weight: 3 };
        return { className: `plan-space kind-${esc(f.properties.kind || 'space')}`, weight: 1, fillOpacity: placement ? 0.05 : 0.15 };
      },
      pointToLayer: (f, latlng) => {
        const kind = f.properties.feature;
        return L.circleMarker(latlng, { radius: kind === 'door' ? 3 : 5, className: `plan-${kind}`, interactive: false });
      },
      onEachFeature: (f, layer) => {
        const p = f.properties;
        if (p.feature === 'space' && p.name) {
          label(layer, p.name, 'room');
          labelled.add(p.room_id);
        }
      },
    });
    group.addLayer(geo);
  }
  for (const room of rooms) {
    // Rooms a plan already drew and labelled are left out; the others are their rectangles.
    if (labelled.has(room.id)) continue;
    const rects = room.rects.map((r) => L.rectangle(L.latLngBounds(ll(r.xmin, r.ymin), ll(r.xmax, r.ymax)),
      { className: 'room-rect', weight: 1, fillOpacity: 0.12, interactive: false }));
    if (!rects.length) continue;
    const biggest = rects.reduce((a, b) => (area(a) >= area(b) ? a : b));
    for (const r of rects) group.addLayer(r);
    label(biggest, room.name, 'room');
  }
  for (const poi of pois) group.addLayer(poiMarker(poi));
  return { group, bounds };
}

function area(rect) {
  const b = rect.getBounds();
  return (b.getNorth() - b.getSouth()) * (b.getEast() - b.getWest());
}
