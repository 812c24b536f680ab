// An x–y plot (xyplot.js) as a file: its title, the scene, the plot and a legend of each
// run's line and marker, drawn by one code on a canvas for a PNG and on an SvgContext
// (svgcanvas.js) for an SVG, so the files show what the page shows.

import { FONT, wrap } from './export.js';
import { SvgContext } from './svgcanvas.js';
import { addMarker, markerFill } from './palette.js';
import { layout, paint, HEIGHT } from './xyplot.js';

const PAD = 12;
const LINE = 18;

function measurer() {
  const probe = document.createElement('canvas').getContext('2d');
  return (text, font) => {
    probe.font = font;
    return probe.measureText(text).width;
  };
}

// The header lines, the legend's rows of items and the whole size, for a plot `width` wide.
function figure(spec, d, width) {
  const measure = measurer();
  const lines = [];
  for (const l of wrap(d.title, width, (t) => measure(t, `600 14px ${FONT}`))) lines.push([l, `600 14px ${FONT}`, '#0f172a']);
  for (const l of wrap(d.caption, width, (t) => measure(t, `12px ${FONT}`))) lines.push([l, `12px ${FONT}`, '#64748b']);
  const rows = [[]];
  let x = 0;
  for (const s of spec.series) {
    const w = 30 + measure(s.label, `12px ${FONT}`) + 18;
    if (x + w > width && rows.at(-1).length) {
      rows.push([]);
      x = 0;
    }
    rows.at(-1).push({ s, x });
    x += w;
  }
  const top = PAD + lines.length * LINE + 4;
  return { lines, rows, top, size: { width: width + 2 * PAD, height: top + HEIGHT + rows.length * LINE + PAD } };
}

function paintFigure(ctx, spec, L, f) {
  ctx.fillStyle = '#ffffff';
  ctx.fillRect(0, 0, f.size.width, f.size.height);
  ctx.textAlign = 'left';
  ctx.textBaseline = 'top';
  f.lines.forEach(([text, font, colour], i) => {
    ctx.font = font;
    ctx.fillStyle = colour;
    ctx.fillText(text, PAD, PAD + i * LINE);
  });
  ctx.save();
  ctx.translate(PAD, f.top);
  paint(ctx, L, spec);
  ctx.restore();
  let y = f.top + HEIGHT + LINE / 2;
  ctx.font = `12px ${FONT}`;
  for (const row of f.rows) {
    for (const { s, x } of row) {
      const left = PAD + x;
      if (spec.mode === 'lines') {
        ctx.strokeStyle = s.style.colour;
        ctx.lineWidth = 2;
        ctx.setLineDash(s.style.dash ?? []);
        ctx.beginPath();
        ctx.moveTo(left, y);
        ctx.lineTo(left + 24, y);
        ctx.stroke();
        ctx.setLineDash([]);
      }
      ctx.beginPath();
      addMarker(ctx, s.style.marker, left + 12, y, 4);
      const fill = markerFill(s.style);
      if (fill !== 'none') {
        ctx.fillStyle = fill;
        ctx.fill();
      }
      ctx.strokeStyle = s.style.colour;
      ctx.lineWidth = 1.25;
      ctx.stroke();
      ctx.fillStyle = '#0f172a';
      ctx.textBaseline = 'middle';
      ctx.fillText(s.label, left + 30, y);
    }
    y += LINE;
  }
}

/** The plot `spec` `width` wide as a PNG canvas, with `d`'s title and caption. */
export function xyCanvas(spec, d, width) {
  const L = layout(spec.series, width);
  const f = figure(spec, d, width);
  const r = window.devicePixelRatio || 1;
  const out = document.createElement('canvas');
  out.width = Math.round(f.size.width * r);
  out.height = Math.round(f.size.height * r);
  const ctx = out.getContext('2d');
  ctx.scale(r, r);
  paintFigure(ctx, spec, L, f);
  return out;
}

/** The plot `spec` `width` wide as an SVG document, with `d`'s title and caption. */
export function xySvg(spec, d, width) {
  const L = layout(spec.series, width);
  const f = figure(spec, d, width);
  const ctx = new SvgContext(f.size.width, f.size.height);
  paintFigure(ctx, spec, L, f);
  return ctx.toString();
}
