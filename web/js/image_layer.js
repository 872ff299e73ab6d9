// A floor's plan image placed by its stored placement. Unrotated, Leaflet's own imageOverlay
// with the image's bounds; turned, the <img> is laid on the map with a CSS matrix computed from
// the placement's corners (floor metres), re-computed after each zoom or pan (hidden while a
// zoom animates, like other non-animated layers), so any rotation lines up exactly.
const L = window.L;

export function ll(x, y) { return L.latLng(y, x); }

const RotatedImage = L.Layer.extend({
  initialize(url, placement, options) {
    this._url = url;
    this._p = placement;
    L.setOptions(this, options);
  },
  onAdd(map) {
    const img = L.DomUtil.create('img', 'leaflet-image-layer leaflet-zoom-hide plan-image rotated');
    img.src = this._url;
    img.alt = this.options.alt || '';
    img.style.transformOrigin = '0 0';
    img.style.width = `${this._p.width_px}px`;
    img.style.height = `${this._p.height_px}px`;
    if (this.options.opacity !== undefined) img.style.opacity = this.options.opacity;
    this._img = img;
    this.getPane().appendChild(img);
    map.on('zoomend viewreset moveend', this._reset, this);
    this._reset();
  },
  onRemove(map) {
    map.off('zoomend viewreset moveend', this._reset, this);
    L.DomUtil.remove(this._img);
  },
  _reset() {
    // corners: bottom-left, bottom-right, top-right, top-left; the image's pixel (0, 0) is its
    // top-left corner, +x along its top edge, +y down its left edge.
    const [bl, , tr, tl] = this._p.corners.map(([x, y]) => this._map.latLngToLayerPoint(ll(x, y)));
    const w = this._p.width_px, h = this._p.height_px;
    const a = (tr.x - tl.x) / w, b = (tr.y - tl.y) / w, c = (bl.x - tl.x) / h, d = (bl.y - tl.y) / h;
    this._img.style.transform = `matrix(${a},${b},${c},${d},${tl.x},${tl.y})`;
  },
});

export function planImageLayer(floorId, placement) {
  const url = `/v1/floors/${floorId}/image`;
  const opts = { opacity: 0.9, alt: 'Floor plan image' };
  if (Math.abs(placement.rotation_deg % 360) < 1e-9) {
    const [bl, , tr] = placement.corners;
    return L.imageOverlay(url, L.latLngBounds(ll(bl[0], bl[1]), ll(tr[0], tr[1])), opts);
  }
  return new RotatedImage(url, placement, opts);
}
