// The Map view's heat map as a file: its drawing (heatmap.js `paint`) under a title, the
// scene it shows and a line on how to read its colours, on a canvas for a PNG or on an
// SvgContext (svgcanvas.js) for an SVG. One drawing code for both, so the files show what
// the page shows.

import { FONT, wrap } from '../draw/export.js';
import { SvgContext } from '../draw/svgcanvas.js';

const PAD = 12;
const LINE = 18;

// The header's lines, wrapped to `width`: `[text, font, colour]`.
function headerLines(measure, width, { title = '', caption = '', key = '' }) {
  const lines = [];
  const add = (text, font, colour) => {
    for (const l of wrap(text, width, (t) => measure(t, font))) lines.push([l, font, colour]);
  };
  add(title, `600 14px ${FONT}`, '#0f172a');
  add(caption, `12px ${FONT}`, '#64748b');
  add(key, `12px ${FONT}`, '#0f172a');
  return lines;
}

// Draws the white ground, the header and the heat map on `ctx`.
function paintAll(ctx, heatmap, L, lines, size) {
  ctx.fillStyle = '#ffffff';
  ctx.fillRect(0, 0, size.width, size.height);
  ctx.textAlign = 'left';
  ctx.textBaseline = 'top';
  lines.forEach(([text, font, colour], i) => {
    ctx.font = font;
    ctx.fillStyle = colour;
    ctx.fillText(text, PAD, PAD + i * LINE);
  });
  ctx.save();
  ctx.translate(PAD, PAD + lines.length * LINE + 4);
  heatmap.paint(ctx, L);
  ctx.restore();
}

function layoutAll(heatmap, d) {
  const L = heatmap.layout();
  const probe = document.createElement('canvas').getContext('2d');
  const measure = (t, font) => {
    probe.font = font;
    return probe.measureText(t).width;
  };
  const lines = headerLines(measure, L.width, d);
  return { L, lines, size: { width: L.width + 2 * PAD, height: PAD + lines.length * LINE + 4 + L.height + PAD } };
}

/** The heat map on a canvas at the screen's pixel density, with `d`'s title, caption and key. */
export function heatmapCanvas(heatmap, d) {
  const { L, lines, size } = layoutAll(heatmap, d);
  const r = window.devicePixelRatio || 1;
  const out = document.createElement('canvas');
  out.width = Math.round(size.width * r);
  out.height = Math.round(size.height * r);
  const ctx = out.getContext('2d');
  ctx.scale(r, r);
  paintAll(ctx, heatmap, L, lines, size);
  return out;
}

/** The heat map as an SVG document, with `d`'s title, caption and key. */
export function heatmapSvg(heatmap, d) {
  const { L, lines, size } = layoutAll(heatmap, d);
  const ctx = new SvgContext(size.width, size.height);
  paintAll(ctx, heatmap, L, lines, size);
  return ctx.toString();
}
