// The radio-map quality rasters, pure functions of RPs and a grid (no DOM): inverse-distance
// weighted mean RSS of one AP, and distance to the nearest RP. Each returns RGBA bytes ready
// for a canvas, row 0 at the top (the floor's largest y).

// Cells across the longer side: fine enough to see a 1 m gap on a 100 m floor, cheap enough
// (<= 240 x 240 cells x RPs) to recompute on every AP change.
export const GRID_CELLS = 240;

export function gridOf(width, height) {
  const cell = Math.max(width, height) / GRID_CELLS;
  return { cell, cols: Math.max(1, Math.ceil(width / cell)), rows: Math.max(1, Math.ceil(height / cell)) };
}

// dBm to colour: weak (blue) to strong (yellow), a perceptual ramp close to viridis.
const RAMP = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
export function rampColour(t) {
  const u = Math.min(1, Math.max(0, t)) * (RAMP.length - 1);
  const i = Math.min(RAMP.length - 2, Math.floor(u));
  const f = u - i;
  return RAMP[i].map((c, k) => Math.round(c + (RAMP[i + 1][k] - c) * f));
}
export function rampCss(t) { return `rgb(${rampColour(t).join(',')})`; }

// samples: [{x, y, v}] (v in dBm). Within `reach` metres of some sample, each cell takes the
// IDW (power 2) of the samples; farther cells stay transparent, so the map never claims a
// signal where nobody measured.
export function idwRaster(samples, width, height, reach, lo, hi) {
  const { cell, cols, rows } = gridOf(width, height);
  const rgba = new Uint8ClampedArray(cols * rows * 4);
  const reach2 = reach * reach;
  for (let r = 0; r < rows; ++r) {
    const y = height - (r + 0.5) * cell;
    for (let c = 0; c < cols; ++c) {
      const x = (c + 0.5) * cell;
      let wsum = 0, vsum = 0, near = Infinity, exact = null;
      for (const s of samples) {
        const dx = s.x - x, dy = s.y - y, d2 = dx * dx + dy * dy;
        if (d2 < near) near = d2;
        if (d2 < 1e-12) { exact = s.v; break; }
        const w = 1 / d2;
        wsum += w;
        vsum += w * s.v;
      }
      if (near > reach2) continue;
      const v = exact !== null ? exact : vsum / wsum;
      const [R, G, B] = rampColour((v - lo) / (hi - lo || 1));
      const o = (r * cols + c) * 4;
      rgba[o] = R; rgba[o + 1] = G; rgba[o + 2] = B; rgba[o + 3] = 255;
    }
  }
  return { rgba, cols, rows };
}

// Cells farther than `gap` metres from every RP, and the share of the floor they cover.
export function gapRaster(points, width, height, gap) {
  const { cell, cols, rows } = gridOf(width, height);
  const rgba = new Uint8ClampedArray(cols * rows * 4);
  const gap2 = gap * gap;
  let count = 0;
  for (let r = 0; r < rows; ++r) {
    const y = height - (r + 0.5) * cell;
    for (let c = 0; c < cols; ++c) {
      const x = (c + 0.5) * cell;
      let far = true;
      for (const p of points) {
        const dx = p.x - x, dy = p.y - y;
        if (dx * dx + dy * dy <= gap2) { far = false; break; }
      }
      if (!far) continue;
      ++count;
      const o = (r * cols + c) * 4;
      // Stripes, so a gap reads as "missing" over any plan colour.
      const stripe = ((r + c) % 6) < 3;
      rgba[o] = 220; rgba[o + 1] = 30; rgba[o + 2] = 60; rgba[o + 3] = stripe ? 150 : 70;
    }
  }
  return { rgba, cols, rows, share: count / (cols * rows) };
}

// A raster as a data: URL (the page's CSP allows data: images).
export function rasterUrl({ rgba, cols, rows }) {
  const canvas = document.createElement('canvas');
  canvas.width = cols;
  canvas.height = rows;
  canvas.getContext('2d').putImageData(new ImageData(rgba, cols, rows), 0, 0);
  return canvas.toDataURL('image/png');
}
