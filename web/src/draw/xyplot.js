// An x–y plot on a canvas, for the Trajectory and Section panels: one curve (`lines`, with a
// dozen of its method's markers along it) or one cloud of markers (`points`) per run, each in
// its method's colour, dash and marker shape (palette.js), on linear axes around the data.
// The drawing takes any canvas-like context, so the same code draws the screen's canvas, an
// exported PNG and, through an SvgContext, an SVG (xyexport.js). Clouds of 10⁴ markers draw
// as one path per run.

import { addMarker, isOpen, markerFill } from './palette.js';
import { finiteExtent, niceTicks, paddedRange } from '../data/dynamics.js';
import { compactTick } from './axes.js';
import { FONT } from './export.js';

export const HEIGHT = 300;
const MARGIN = { left: 60, right: 12, top: 10, bottom: 42 };

/** The plot's geometry for `series` (`[{xs, ys}]`) in a `width` × `height` box. */
export function layout(series, width, height = HEIGHT) {
  const box = { left: MARGIN.left, top: MARGIN.top, width: Math.max(40, width - MARGIN.left - MARGIN.right), height: Math.max(40, height - MARGIN.top - MARGIN.bottom) };
  const xr = paddedRange(finiteExtent(series.map((s) => s.xs)));
  const yr = paddedRange(finiteExtent(series.map((s) => s.ys)));
  return {
    width,
    height,
    box,
    xr,
    yr,
    xt: niceTicks(xr[0], xr[1], Math.max(2, Math.round(box.width / 90))),
    yt: niceTicks(yr[0], yr[1], Math.max(2, Math.round(box.height / 50))),
  };
}

/**
 * Draws the plot on `ctx` (its origin at the plot's top left): axes, grid, labels, then each
 * series `{style, xs, ys, width}` as `mode` says (`lines` or `points`).
 */
export function paint(ctx, L, { series, mode, xLabel, yLabel }) {
  const { box, xr, yr } = L;
  const px = (x) => box.left + ((x - xr[0]) / (xr[1] - xr[0])) * box.width;
  const py = (y) => box.top + (1 - (y - yr[0]) / (yr[1] - yr[0])) * box.height;
  ctx.fillStyle = '#ffffff';
  ctx.fillRect(0, 0, L.width, L.height);
  ctx.lineWidth = 1;
  ctx.setLineDash([]);
  ctx.strokeStyle = '#e2e8f0';
  ctx.beginPath();
  for (const x of L.xt) {
    ctx.moveTo(px(x), box.top);
    ctx.lineTo(px(x), box.top + box.height);
  }
  for (const y of L.yt) {
    ctx.moveTo(box.left, py(y));
    ctx.lineTo(box.left + box.width, py(y));
  }
  ctx.stroke();
  ctx.strokeStyle = '#cbd5e1';
  ctx.strokeRect(box.left, box.top, box.width, box.height);
  ctx.fillStyle = '#475569';
  ctx.font = `11px ${FONT}`;
  ctx.textAlign = 'center';
  ctx.textBaseline = 'top';
  for (const x of L.xt) ctx.fillText(compactTick(x), px(x), box.top + box.height + 4);
  ctx.textAlign = 'right';
  ctx.textBaseline = 'middle';
  for (const y of L.yt) ctx.fillText(compactTick(y), box.left - 5, py(y));
  ctx.font = `12px ${FONT}`;
  ctx.textAlign = 'center';
  ctx.textBaseline = 'bottom';
  ctx.fillText(xLabel, box.left + box.width / 2, L.height - 2);
  ctx.save();
  ctx.translate(12, box.top + box.height / 2);
  ctx.rotate(-Math.PI / 2);
  ctx.textBaseline = 'middle';
  ctx.fillText(yLabel, 0, 0);
  ctx.restore();

  ctx.save();
  ctx.beginPath();
  ctx.rect(box.left - 4, box.top - 4, box.width + 8, box.height + 8);
  ctx.clip();
  series.forEach((s, i) => {
    const n = Math.min(s.xs.length, s.ys.length);
    if (mode === 'lines') {
      ctx.strokeStyle = s.style.colour;
      ctx.lineWidth = s.width ?? 1.5;
      ctx.setLineDash(s.style.dash ?? []);
      ctx.beginPath();
      let pen = false;
      for (let k = 0; k < n; k++) {
        const x = s.xs[k];
        const y = s.ys[k];
        if (!Number.isFinite(x) || !Number.isFinite(y)) {
          pen = false;
          continue;
        }
        if (pen) ctx.lineTo(px(x), py(y));
        else ctx.moveTo(px(x), py(y));
        pen = true;
      }
      ctx.stroke();
      ctx.setLineDash([]);
      markers(ctx, s, sparse(n, i, series.length), px, py, 3.5);
    } else {
      markers(ctx, s, null, px, py, n > 2000 ? 2 : 3);
    }
  });
  ctx.restore();
}

/** About a dozen indices out of `n`, offset by the series' place `i` of `count`, so that the
 *  markers of curves drawn on top of each other fall side by side. */
export function sparse(n, i, count, per = 12) {
  if (n === 0) return [];
  const out = [];
  for (let k = 0; k < per; k++) {
    const j = Math.min(n - 1, Math.floor(((k + (i + 0.5) / Math.max(1, count)) / per) * n));
    if (out.at(-1) !== j) out.push(j);
  }
  return out;
}

// The markers of series `s` at `indices` (every point when null). On a canvas, stamps of one
// pre-drawn marker (a path of 10⁴ circles fills far slower); elsewhere (SVG) one path.
function markers(ctx, s, indices, px, py, r) {
  const n = Math.min(s.xs.length, s.ys.length);
  const at = indices ?? { length: n, [Symbol.iterator]: function* () { for (let k = 0; k < n; k++) yield k; } };
  if (typeof ctx.drawImage === 'function' && typeof ctx.getTransform === 'function') {
    const scale = ctx.getTransform().a || 1;
    const sprite = stamp(s.style, r, scale);
    const half = sprite.width / scale / 2;
    const size = sprite.width / scale;
    for (const k of at) {
      const x = s.xs[k];
      const y = s.ys[k];
      if (Number.isFinite(x) && Number.isFinite(y)) ctx.drawImage(sprite, px(x) - half, py(y) - half, size, size);
    }
    return;
  }
  ctx.beginPath();
  for (const k of at) {
    const x = s.xs[k];
    const y = s.ys[k];
    if (Number.isFinite(x) && Number.isFinite(y)) addMarker(ctx, s.style.marker, px(x), py(y), r);
  }
  outline(ctx, s.style);
}

// Fills and strokes the current path as a marker of `style`: a filled marker needs no
// outline; a hollow or open one is its outline.
function outline(ctx, style) {
  const fill = markerFill(style);
  if (fill !== 'none') {
    ctx.fillStyle = fill;
    ctx.fill();
  }
  if (isOpen(style.marker) || style.hollow) {
    ctx.strokeStyle = style.colour;
    ctx.lineWidth = 1.25;
    ctx.stroke();
  }
}

// One marker of `style` and radius r drawn at `scale` device pixels per CSS pixel.
const stamps = new Map();
function stamp(style, r, scale) {
  const key = `${style.colour}|${style.marker}|${style.hollow}|${r}|${scale}`;
  let c = stamps.get(key);
  if (c) return c;
  const side = Math.ceil((2 * r + 4) * scale);
  c = document.createElement('canvas');
  c.width = c.height = side;
  const ctx = c.getContext('2d');
  ctx.scale(scale, scale);
  ctx.beginPath();
  addMarker(ctx, style.marker, side / scale / 2, side / scale / 2, r);
  outline(ctx, style);
  stamps.set(key, c);
  return c;
}

/** A plot on a canvas in `target`, as wide as its container, redrawn by `draw(spec)`. */
export class XYPlot {
  constructor(target, container) {
    this.container = container;
    this.canvas = document.createElement('canvas');
    this.canvas.setAttribute('role', 'img');
    this.canvas.className = 'xy-canvas';
    target.append(this.canvas);
    this.spec = null;
    this.drawMs = null;
    new ResizeObserver(() => this.spec && this.draw(this.spec)).observe(container);
  }

  /** The width to draw at: the container's, less the card's padding. */
  width() {
    return Math.max(220, Math.floor(this.container.clientWidth - 34));
  }

  draw(spec) {
    const start = performance.now();
    this.spec = spec;
    const width = this.width();
    const r = window.devicePixelRatio || 1;
    if (this.canvas.width !== Math.round(width * r) || this.canvas.height !== Math.round(HEIGHT * r)) {
      this.canvas.width = Math.round(width * r);
      this.canvas.height = Math.round(HEIGHT * r);
      this.canvas.style.width = `${width}px`;
      this.canvas.style.height = `${HEIGHT}px`;
    }
    const ctx = this.canvas.getContext('2d');
    ctx.setTransform(r, 0, 0, r, 0, 0);
    this.layout = layout(spec.series, width);
    paint(ctx, this.layout, spec);
    this.drawMs = performance.now() - start;
  }
}
