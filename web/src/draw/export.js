// Exporting a uPlot chart as a file. One drawing code for both formats: a frame (title,
// caption, the chart, a legend with each method's line and marker) drawn on a canvas context
// for a PNG, around the chart's own pixels, and on an SvgContext (svgcanvas.js, the page's one
// SVG writer) for an SVG, around the chart redrawn as vectors from uPlot's public API: its
// scales (`valToPos`), its plotting box (`bbox`), its series and data, and the ticks and
// labels uPlot chose, which `withTicks` records from the axis options' own callbacks as the
// chart draws. A plot card gets both as small buttons; the file is named after the scene and
// the plot.

import { download, el } from './dom.js';
import { addMarker, markerFill } from './palette.js';
import { SvgContext } from './svgcanvas.js';

export const FONT = 'system-ui, -apple-system, "Segoe UI", Roboto, Arial, sans-serif';

/** uPlot chart → per axis index, the ticks of its last draw: `splits` (values on the scale)
 *  and `labels` (the text at each, null or '' where uPlot writes none). */
const TICKS = new WeakMap();

/**
 * A uPlot plugin that records each axis's ticks as the chart draws them: uPlot hands the axis
 * options' `grid.filter` every tick value and `values` their labels. Both are wrapped, and
 * what they return is unchanged. Charts that export as SVG carry it (`plugins: [withTicks()]`).
 */
export function withTicks() {
  const slot = (u, i) => {
    if (!TICKS.has(u)) TICKS.set(u, []);
    const axes = TICKS.get(u);
    axes[i] ??= { splits: [], labels: [] };
    return axes[i];
  };
  return {
    opts: (u, opts) => ({
      ...opts,
      axes: (opts.axes ?? []).map((axis) => {
        const { values, grid = {} } = axis;
        return {
          ...axis,
          grid: {
            ...grid,
            filter: (self, splits, i, ...rest) => {
              slot(self, i).splits = [...splits];
              return grid.filter ? grid.filter(self, splits, i, ...rest) : splits;
            },
          },
          values: (self, splits, i, ...rest) => {
            const labels = typeof values === 'function' ? values(self, splits, i, ...rest) : splits.map((v) => (v === null ? null : String(v)));
            slot(self, i).labels = [...labels];
            return labels;
          },
        };
      }),
    }),
  };
}

/** The ticks `withTicks` recorded for axis `i` of `u`: `[{value, label}]`, label null where
 *  uPlot wrote none; empty before a draw or without the plugin. */
export function axisTicks(u, i) {
  const t = TICKS.get(u)?.[i];
  if (!t) return [];
  return t.splits.map((value, k) => ({ value, label: t.labels[k] === '' || t.labels[k] === undefined ? null : t.labels[k] }));
}

/**
 * "PNG" and "SVG" buttons for a chart. `describe()` gives `{title, caption, stem, styles,
 * floor}` at click time (the file is `<stem>.png`; optional: `styles[i]`, the look of series
 * i + 1; `floor`, the y of a round-off floor line); `chart()` the uPlot instance.
 */
export function exportButtons(chart, describe) {
  return fileButtons(describe, { png: (d) => chartCanvas(chart(), d), svg: (d) => chartSvg(chart(), d) });
}

/** "PNG" and "SVG" buttons for any picture: `png(d)` draws it on a canvas, `svg(d)` writes
 *  it as SVG text, `d` being `describe()` at click time (with the file's `stem`). */
export function fileButtons(describe, { png, svg }) {
  const box = el('span', 'plot-export');
  const pngButton = el('button', 'secondary small export-png', 'PNG');
  const svgButton = el('button', 'secondary small export-svg', 'SVG');
  pngButton.type = svgButton.type = 'button';
  pngButton.title = 'Download this plot as a PNG image';
  svgButton.title = 'Download this plot as an SVG drawing';
  pngButton.addEventListener('click', () => {
    const d = describe();
    png(d).toBlob((blob) => blob && download(`${d.stem}.png`, 'image/png', blob), 'image/png');
  });
  svgButton.addEventListener('click', () => {
    const d = describe();
    download(`${d.stem}.svg`, 'image/svg+xml', svg(d));
  });
  box.append(pngButton, svgButton);
  return box;
}

// The legend entries: shown series after x, with colour, width, dash, marker and label.
function entries(u, styles) {
  return u.series
    .map((s, i) => ({ s, i }))
    .filter(({ s, i }) => i > 0 && s.show !== false)
    .map(({ s, i }) => ({
      label: String(s.label ?? ''),
      color: typeof s.stroke === 'function' ? s.stroke(u, i) : s.stroke ?? '#000',
      width: s.width ?? 1,
      dash: s.dash ?? null,
      style: styles?.[i - 1] ?? null,
      index: i,
    }));
}

/** Words of `text` in lines no wider than `width` (measured with `measure`). */
export function wrap(text, width, measure) {
  const lines = [];
  let line = '';
  for (const word of String(text ?? '').split(/\s+/).filter(Boolean)) {
    const next = line ? `${line} ${word}` : word;
    if (line && measure(next) > width) {
      lines.push(line);
      line = word;
    } else line = next;
  }
  if (line) lines.push(line);
  return lines;
}

// Where the frame's parts go, in units of `r` (device pixels per CSS pixel): the caption's
// lines, the chart's top, the legend's rows (entries side by side, wrapped) and the size.
function frameLayout(ctx, u, { title = '', caption = '', styles = null }, r) {
  const pad = 12 * r;
  const line = 18 * r;
  const width = u.width * r + 2 * pad;
  ctx.font = `${12 * r}px ${FONT}`;
  const captionLines = wrap(caption, width - 2 * pad, (t) => ctx.measureText(t).width);
  const rows = [[]];
  let x = 0;
  for (const item of entries(u, styles)) {
    const w = 30 * r + ctx.measureText(item.label).width + 18 * r;
    if (x + w > width - 2 * pad && rows.at(-1).length) {
      rows.push([]);
      x = 0;
    }
    rows.at(-1).push({ ...item, x });
    x += w;
  }
  const chartTop = pad + (title ? line : 0) + captionLines.length * line;
  const chartBottom = chartTop + u.height * r;
  return { r, pad, line, width, height: chartBottom + rows.length * line + pad, title, captionLines, chartTop, chartBottom, rows };
}

// The frame on `ctx` (a canvas's or an SvgContext), white under it; `chart(x, y)` draws the
// chart with its top left at (x, y).
function drawFrame(ctx, L, chart) {
  const { r, pad, line } = L;
  ctx.fillStyle = '#fff';
  ctx.fillRect(0, 0, L.width, L.height);
  let y = pad;
  ctx.textBaseline = 'top';
  ctx.textAlign = 'left';
  if (L.title) {
    ctx.fillStyle = '#0f172a';
    ctx.font = `600 ${14 * r}px ${FONT}`;
    ctx.fillText(L.title, pad, y);
    y += line;
  }
  ctx.font = `${12 * r}px ${FONT}`;
  ctx.fillStyle = '#64748b';
  for (const l of L.captionLines) {
    ctx.fillText(l, pad, y);
    y += line;
  }
  chart(pad, L.chartTop);
  y = L.chartBottom;
  ctx.textBaseline = 'middle';
  for (const row of L.rows) {
    for (const item of row) {
      const mid = y + line / 2;
      ctx.strokeStyle = item.color;
      ctx.lineWidth = Math.max(2, item.width) * r;
      ctx.setLineDash(item.dash ? item.dash.map((d) => d * r) : []);
      ctx.beginPath();
      ctx.moveTo(pad + item.x, mid);
      ctx.lineTo(pad + item.x + 24 * r, mid);
      ctx.stroke();
      ctx.setLineDash([]);
      if (item.style) marker(ctx, item, pad + item.x + 12 * r, [mid], 4 * r, 1.25 * r);
      ctx.fillStyle = '#0f172a';
      ctx.fillText(item.label, pad + item.x + 30 * r, mid);
    }
    y += line;
  }
}

// Markers of a legend entry's (or series') shape at `ys` (all at x when one x is given, else
// `xs[k]`, `ys[k]`): one path, filled as the method's look says, then outlined.
function marker(ctx, item, xs, ys, size, width) {
  ctx.beginPath();
  ys.forEach((y, k) => addMarker(ctx, item.style.marker, Array.isArray(xs) ? xs[k] : xs, y, size));
  ctx.lineWidth = width;
  ctx.strokeStyle = item.color;
  const fill = markerFill(item.style, item.color);
  if (fill !== 'none') {
    ctx.fillStyle = fill;
    ctx.fill();
  }
  ctx.stroke();
}

/** A canvas: title, caption, the chart as drawn, then the legend, on white. */
export function chartCanvas(u, d = {}) {
  const src = u.ctx.canvas;
  const r = src.width / u.width || 1;
  const out = document.createElement('canvas');
  const ctx = out.getContext('2d');
  const L = frameLayout(ctx, u, d, r);
  out.width = L.width;
  out.height = L.height;
  drawFrame(ctx, L, (x, y) => ctx.drawImage(src, x, y));
  return out;
}

/** The chart as an SVG document: title, caption, axes with their ticks, the series, legend. */
export function chartSvg(u, d = {}) {
  const ctx = new SvgContext(0, 0);
  const L = frameLayout(ctx, u, d, 1);
  ctx.width = L.width;
  ctx.height = L.height;
  drawFrame(ctx, L, (x, y) => {
    ctx.save();
    ctx.translate(x, y);
    vectorChart(ctx, u, d);
    ctx.restore();
  });
  return ctx.toString();
}

// The chart redrawn as vectors with its top left at the origin: grid and tick labels where
// uPlot put them, the axes' labels, the plotting box, the round-off floor, each series as a
// path broken at gaps (unless it spans them), and the markers where uPlot puts them.
function vectorChart(ctx, u, { styles = null, floor = null }) {
  const r = u.ctx.canvas.width / u.width || 1;
  const box = { left: u.bbox.left / r, top: u.bbox.top / r, width: u.bbox.width / r, height: u.bbox.height / r };
  const right = box.left + box.width;
  const bottom = box.top + box.height;
  ctx.font = `12px ${FONT}`;
  ctx.lineWidth = 1;
  u.axes.forEach((axis, ai) => {
    if (axis.show === false) return;
    const vertical = axis.side % 2 === 1;
    const scale = axis.scale ?? (ai === 0 ? 'x' : 'y');
    for (const { value, label } of axisTicks(u, ai)) {
      const p = value === null ? NaN : u.valToPos(value, scale);
      if (!Number.isFinite(p)) continue;
      ctx.strokeStyle = '#e2e8f0';
      ctx.beginPath();
      if (vertical) {
        ctx.moveTo(box.left, box.top + p);
        ctx.lineTo(right, box.top + p);
      } else {
        ctx.moveTo(box.left + p, box.top);
        ctx.lineTo(box.left + p, bottom);
      }
      ctx.stroke();
      if (label === null) continue;
      ctx.fillStyle = '#475569';
      ctx.textAlign = vertical ? 'right' : 'center';
      ctx.textBaseline = vertical ? 'middle' : 'top';
      if (vertical) ctx.fillText(label, box.left - 6, box.top + p);
      else ctx.fillText(label, box.left + p, bottom + 6);
    }
    if (!axis.label) return;
    ctx.fillStyle = '#475569';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'middle';
    if (vertical) {
      ctx.save();
      ctx.translate(12, box.top + box.height / 2);
      ctx.rotate(-Math.PI / 2);
      ctx.fillText(axis.label, 0, 0);
      ctx.restore();
    } else ctx.fillText(axis.label, box.left + box.width / 2, bottom + 36);
  });
  ctx.strokeStyle = '#cbd5e1';
  ctx.strokeRect(box.left, box.top, box.width, box.height);
  // The round-off floor the canvas draws in a hook, when the chart has one.
  const fy = floor ? u.valToPos(floor, 'y') : NaN;
  if (Number.isFinite(fy)) {
    ctx.strokeStyle = '#64748b';
    ctx.setLineDash([6, 4]);
    ctx.beginPath();
    ctx.moveTo(box.left, box.top + fy);
    ctx.lineTo(right, box.top + fy);
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.fillStyle = '#64748b';
    ctx.font = `11px ${FONT}`;
    ctx.textAlign = 'right';
    ctx.textBaseline = 'bottom';
    ctx.fillText('round-off floor', right - 4, box.top + fy - 4);
  }
  ctx.save();
  ctx.beginPath();
  ctx.rect(box.left, box.top, box.width, box.height);
  ctx.clip();
  for (const item of entries(u, styles)) seriesPath(ctx, u, item, box);
  ctx.restore();
}

// One series: its line, then its markers at the points its `points.filter` picks.
function seriesPath(ctx, u, item, box) {
  const s = u.series[item.index];
  const xs = u.data[0];
  const ys = u.data[item.index] ?? [];
  const at = (k) => {
    const y = ys[k];
    const px = u.valToPos(xs[k], 'x');
    const py = y === null || y === undefined ? NaN : u.valToPos(y, s.scale ?? 'y');
    return Number.isFinite(px) && Number.isFinite(py) ? [box.left + px, box.top + py] : null;
  };
  ctx.beginPath();
  let pen = false;
  let drawn = false;
  for (let k = 0; k < xs.length; k++) {
    const p = at(k);
    if (!p) {
      if (!(s.spanGaps && (ys[k] === null || ys[k] === undefined))) pen = false;
      continue;
    }
    if (pen) ctx.lineTo(...p);
    else ctx.moveTo(...p);
    pen = drawn = true;
  }
  if (drawn) {
    ctx.strokeStyle = item.color;
    ctx.lineWidth = item.width;
    ctx.setLineDash(item.dash ?? []);
    ctx.stroke();
    ctx.setLineDash([]);
  }
  const picked = item.style && typeof s.points?.filter === 'function' ? s.points.filter(u, item.index, true, null) : null;
  if (!Array.isArray(picked) || !picked.length) return;
  const points = picked.map(at).filter(Boolean);
  if (points.length) marker(ctx, item, points.map((p) => p[0]), points.map((p) => p[1]), 3.5, 1.25);
}
