// Drawing a method's look (palette.js) with uPlot: the series options (colour, dash, width,
// markers of its shape), the legend's swatch of line and marker, and the same swatch as SVG
// for tables and the form. On a curve of many points the markers are sparse, a dozen or so,
// staggered from series to series so that coinciding curves still show every marker.

import { addMarker, isOpen, markerFill } from './palette.js';
import { SvgContext } from './svgcanvas.js';

const SVG = 'http://www.w3.org/2000/svg';

/**
 * uPlot series options for a method's `style`: `width` the line width; `size` the marker's
 * diameter in CSS px; `sparse` marks a dozen points or so (a curve of many points), else
 * every point. Add `label`, `value`, … to the result.
 */
export function seriesStyle(style, { width = 2, size = 7, sparse = true } = {}) {
  return {
    stroke: style.colour,
    dash: style.dash ?? undefined,
    width,
    points: {
      show: false,
      size,
      width: 1.25,
      stroke: style.colour,
      fill: style.hollow ? '#fff' : style.colour,
      dash: [],
      filter: (u, si) => (sparse ? sparseIndices(u, si) : everyIndex(u, si)),
      paths: (u, si, i0, i1, idxs) => markerPaths(u, si, idxs ?? [], style, size),
    },
  };
}

function everyIndex(u, si) {
  const ys = u.data[si] ?? [];
  const out = [];
  for (let i = 0; i < ys.length; i++) if (ys[i] !== null && ys[i] !== undefined) out.push(i);
  return out;
}

// About one marker per 80 px of plot, at x positions offset by the series' place so that the
// markers of curves drawn on top of each other fall side by side.
function sparseIndices(u, si) {
  const xs = u.data[0] ?? [];
  const ys = u.data[si] ?? [];
  const { min, max } = u.scales.x;
  if (!xs.length || !(max > min)) return [];
  const count = Math.max(4, Math.min(14, Math.round(u.bbox.width / devicePixelRatio / 80)));
  const phase = (si - 0.5) / Math.max(1, u.series.length - 1);
  const out = [];
  for (let k = 0; k < count; k++) {
    const target = min + ((k + phase) / count) * (max - min);
    let i = lowerBound(xs, target);
    // The nearest point of this series at or after the target, then before it.
    let j = i;
    while (j < xs.length && j < i + 50 && (ys[j] === null || ys[j] === undefined)) j++;
    if (j >= xs.length || ys[j] === null || ys[j] === undefined) {
      j = Math.min(i, xs.length - 1);
      while (j >= 0 && j > i - 50 && (ys[j] === null || ys[j] === undefined)) j--;
    }
    if (j >= 0 && ys[j] !== null && ys[j] !== undefined && out[out.length - 1] !== j) out.push(j);
  }
  return out;
}

function lowerBound(xs, v) {
  let lo = 0;
  let hi = xs.length;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (xs[mid] < v) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

function markerPaths(u, si, idxs, style, size) {
  const path = new Path2D();
  const r = (size / 2) * devicePixelRatio;
  const xs = u.data[0];
  const ys = u.data[si];
  for (const i of idxs) {
    if (ys[i] === null || ys[i] === undefined) continue;
    addMarker(path, style.marker, u.valToPos(xs[i], 'x', true), u.valToPos(ys[i], u.series[si].scale ?? 'y', true), r);
  }
  const { left, top, width, height } = u.bbox;
  const clip = new Path2D();
  clip.rect(left - r, top - r, width + 2 * r, height + 2 * r);
  return { stroke: path, fill: isOpen(style.marker) ? null : path, clip, flags: 3 };
}

/** An SVG swatch of a method's look: a short line in its colour and dash with its marker,
 *  drawn by the page's one SVG writer (svgcanvas.js). */
export function swatch(style, { width = 28, height = 12 } = {}) {
  const ctx = new SvgContext(width, height);
  const y = height / 2;
  ctx.strokeStyle = style.colour;
  ctx.lineWidth = 2;
  ctx.setLineDash(style.dash ? style.dash.map((d) => d * 0.6) : []);
  ctx.beginPath();
  ctx.moveTo(1, y);
  ctx.lineTo(width - 1, y);
  ctx.stroke();
  ctx.setLineDash([]);
  ctx.beginPath();
  addMarker(ctx, style.marker, width / 2, y, Math.min(4.5, height / 2 - 1));
  ctx.lineWidth = 1.25;
  const fill = markerFill(style);
  if (fill !== 'none') {
    ctx.fillStyle = fill;
    ctx.fill();
  }
  ctx.stroke();
  const svg = document.createElementNS(SVG, 'svg');
  svg.setAttribute('class', 'method-swatch');
  svg.setAttribute('width', width);
  svg.setAttribute('height', height);
  svg.setAttribute('viewBox', `0 0 ${width} ${height}`);
  svg.setAttribute('aria-hidden', 'true');
  svg.innerHTML = ctx.content();
  svg.dataset.colour = style.colour;
  svg.dataset.marker = style.marker;
  return svg;
}

/** Puts each series' swatch in place of uPlot's legend marker (`styles[i]` for series i + 1;
 *  a legend that is not live has no row for the x series). */
export function legendSwatches(u, styles) {
  const rows = u.root.querySelectorAll('.u-legend .u-series');
  const first = rows.length - (u.series.length - 1);
  styles.forEach((style, i) => {
    const marker = rows[first + i]?.querySelector('.u-marker');
    if (!marker || !style) return;
    marker.removeAttribute('style');
    marker.classList.add('has-swatch');
    marker.replaceChildren(swatch(style));
  });
}
