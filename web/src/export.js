// Exporting a uPlot chart as a file: PNG (the chart's canvas with its title, the scene it
// shows and a legend drawn around it) and SVG (the same chart redrawn as vector paths from
// uPlot's scales: axes, ticks, grid, one path per series, legend). A plot card gets both as
// small buttons; the file is named after the scene and the plot. Given the methods' looks
// (palette.js), the legend and the SVG carry each method's marker too.

import { download, el } from './dom.js';
import { addMarker, markerFill, svgPen } from './palette.js';
import { esc } from './svgcanvas.js';

export const FONT = 'system-ui, -apple-system, "Segoe UI", Roboto, Arial, sans-serif';

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

/** A canvas: title, caption, the chart as drawn, then the legend, on white. */
export function chartCanvas(u, { title = '', caption = '', styles = null } = {}) {
  const src = u.ctx.canvas;
  const r = src.width / u.width || 1;
  const pad = 12 * r;
  const line = 18 * r;
  const out = document.createElement('canvas');
  const ctx = out.getContext('2d');
  const width = src.width + 2 * pad;
  ctx.font = `${12 * r}px ${FONT}`;
  const captionLines = wrap(caption, width - 2 * pad, (t) => ctx.measureText(t).width);
  const items = entries(u, styles);
  // Legend rows: entries side by side, wrapped.
  const rows = [[]];
  let x = 0;
  for (const item of items) {
    const w = 30 * r + ctx.measureText(item.label).width + 18 * r;
    if (x + w > width - 2 * pad && rows.at(-1).length) {
      rows.push([]);
      x = 0;
    }
    rows.at(-1).push({ ...item, x });
    x += w;
  }
  out.width = width;
  out.height = pad + (title ? line : 0) + captionLines.length * line + src.height + rows.length * line + pad;
  ctx.fillStyle = '#fff';
  ctx.fillRect(0, 0, out.width, out.height);
  let y = pad;
  ctx.textBaseline = 'top';
  if (title) {
    ctx.fillStyle = '#0f172a';
    ctx.font = `600 ${14 * r}px ${FONT}`;
    ctx.fillText(title, pad, y);
    y += line;
  }
  ctx.font = `${12 * r}px ${FONT}`;
  ctx.fillStyle = '#64748b';
  for (const l of captionLines) {
    ctx.fillText(l, pad, y);
    y += line;
  }
  ctx.drawImage(src, pad, y);
  y += src.height;
  ctx.textBaseline = 'middle';
  for (const row of rows) {
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
      if (item.style) {
        const mark = new Path2D();
        addMarker(mark, item.style.marker, pad + item.x + 12 * r, mid, 4 * r);
        ctx.lineWidth = 1.25 * r;
        const fill = markerFill(item.style, item.color);
        if (fill !== 'none') {
          ctx.fillStyle = fill;
          ctx.fill(mark);
        }
        ctx.stroke(mark);
      }
      ctx.fillStyle = '#0f172a';
      ctx.fillText(item.label, pad + item.x + 30 * r, mid);
    }
    y += line;
  }
  return out;
}

const n = (v) => Number(v.toFixed(2));

/** The chart as an SVG document: title, caption, axes with their ticks, the series, legend. */
export function chartSvg(u, { title = '', caption = '', styles = null, floor = null } = {}) {
  const r = u.ctx.canvas.width / u.width || 1;
  const box = { left: u.bbox.left / r, top: u.bbox.top / r, width: u.bbox.width / r, height: u.bbox.height / r };
  const head = (title ? 22 : 0) + (caption ? 18 : 0) + 8;
  const items = entries(u, styles);
  const legendTop = head + u.height + 8;
  const W = u.width + 16;
  const H = legendTop + 20 * Math.ceil(items.length / 4) + 8;
  const parts = [`<svg xmlns="http://www.w3.org/2000/svg" width="${W}" height="${H}" viewBox="0 0 ${W} ${H}" font-family="${esc(FONT)}" font-size="12">`, `<rect width="100%" height="100%" fill="#fff"/>`];
  if (title) parts.push(`<text x="8" y="18" font-size="14" font-weight="600" fill="#0f172a">${esc(title)}</text>`);
  if (caption) parts.push(`<text x="8" y="${title ? 36 : 18}" fill="#64748b">${esc(caption)}</text>`);
  parts.push(`<g transform="translate(8 ${head})">`);
  parts.push(`<defs><clipPath id="plot-area"><rect x="${n(box.left)}" y="${n(box.top)}" width="${n(box.width)}" height="${n(box.height)}"/></clipPath></defs>`);
  // Axes: grid lines and tick labels where uPlot put them, the axis label.
  u.axes.forEach((axis, ai) => {
    if (axis.show === false || !axis._splits) return;
    const vertical = axis.side % 2 === 1;
    const scale = axis.scale ?? (ai === 0 ? 'x' : 'y');
    const values = axis._values ?? [];
    axis._splits.forEach((v, k) => {
      const p = u.valToPos(v, scale);
      if (!Number.isFinite(p)) return;
      const label = values[k];
      if (vertical) {
        const y = n(box.top + p);
        parts.push(`<line x1="${n(box.left)}" x2="${n(box.left + box.width)}" y1="${y}" y2="${y}" stroke="#e2e8f0"/>`);
        if (label !== null && label !== undefined) parts.push(`<text x="${n(box.left - 6)}" y="${y}" text-anchor="end" dominant-baseline="middle" fill="#475569">${esc(label)}</text>`);
      } else {
        const x = n(box.left + p);
        parts.push(`<line x1="${x}" x2="${x}" y1="${n(box.top)}" y2="${n(box.top + box.height)}" stroke="#e2e8f0"/>`);
        if (label !== null && label !== undefined) parts.push(`<text x="${x}" y="${n(box.top + box.height + 16)}" text-anchor="middle" fill="#475569">${esc(label)}</text>`);
      }
    });
    if (axis.label) {
      if (vertical) parts.push(`<text transform="translate(12 ${n(box.top + box.height / 2)}) rotate(-90)" text-anchor="middle" fill="#475569">${esc(axis.label)}</text>`);
      else parts.push(`<text x="${n(box.left + box.width / 2)}" y="${n(box.top + box.height + 36)}" text-anchor="middle" fill="#475569">${esc(axis.label)}</text>`);
    }
  });
  parts.push(`<rect x="${n(box.left)}" y="${n(box.top)}" width="${n(box.width)}" height="${n(box.height)}" fill="none" stroke="#cbd5e1"/>`);
  // The round-off floor the canvas draws in a hook, when the chart has one.
  const fy = floor ? u.valToPos(floor, 'y') : NaN;
  if (Number.isFinite(fy)) {
    const y = n(box.top + fy);
    parts.push(`<line x1="${n(box.left)}" x2="${n(box.left + box.width)}" y1="${y}" y2="${y}" stroke="#64748b" stroke-dasharray="6 4"/>`);
    parts.push(`<text x="${n(box.left + box.width - 4)}" y="${n(box.top + fy - 4)}" text-anchor="end" font-size="11" fill="#64748b">round-off floor</text>`);
  }
  // Series: a path through the drawable points, broken at gaps unless the series spans them.
  parts.push('<g clip-path="url(#plot-area)" fill="none" stroke-linejoin="round">');
  for (const item of items) {
    const s = u.series[item.index];
    const xs = u.data[0];
    const ys = u.data[item.index] ?? [];
    let d = '';
    let pen = false;
    for (let k = 0; k < xs.length; k++) {
      const y = ys[k];
      const px = u.valToPos(xs[k], 'x');
      const py = y === null || y === undefined ? NaN : u.valToPos(y, s.scale ?? 'y');
      if (!Number.isFinite(px) || !Number.isFinite(py)) {
        if (!(s.spanGaps && (y === null || y === undefined))) pen = false;
        continue;
      }
      d += `${pen ? 'L' : 'M'}${n(box.left + px)} ${n(box.top + py)}`;
      pen = true;
    }
    const dash = item.dash ? ` stroke-dasharray="${item.dash.join(' ')}"` : '';
    if (d) parts.push(`<path d="${d}" stroke="${esc(item.color)}" stroke-width="${item.width}"${dash}><title>${esc(item.label)}</title></path>`);
    // The markers where uPlot puts them (its points filter), in the method's shape.
    const at = item.style && typeof s.points?.filter === 'function' ? s.points.filter(u, item.index, true, null) : null;
    if (Array.isArray(at) && at.length) {
      const pen = svgPen();
      for (const k of at) {
        const px = u.valToPos(xs[k], 'x');
        const py = ys[k] === null || ys[k] === undefined ? NaN : u.valToPos(ys[k], s.scale ?? 'y');
        if (Number.isFinite(px) && Number.isFinite(py)) addMarker(pen, item.style.marker, box.left + px, box.top + py, 3.5);
      }
      const fill = markerFill(item.style, item.color);
      parts.push(`<path d="${pen.d}" stroke="${esc(item.color)}" stroke-width="1.25" fill="${esc(fill)}"/>`);
    }
  }
  parts.push('</g></g>');
  items.forEach((item, k) => {
    const x = 8 + (k % 4) * (W / 4);
    const y = legendTop + 20 * Math.floor(k / 4) + 10;
    const dash = item.dash ? ` stroke-dasharray="${item.dash.join(' ')}"` : '';
    parts.push(`<line x1="${n(x)}" x2="${n(x + 22)}" y1="${y}" y2="${y}" stroke="${esc(item.color)}" stroke-width="3"${dash}/>`);
    if (item.style) {
      const pen = svgPen();
      addMarker(pen, item.style.marker, x + 11, y, 4);
      const fill = markerFill(item.style, item.color);
      parts.push(`<path d="${pen.d}" stroke="${esc(item.color)}" stroke-width="1.25" fill="${esc(fill)}"/>`);
    }
    parts.push(`<text x="${n(x + 28)}" y="${y}" dominant-baseline="middle" fill="#0f172a">${esc(item.label)}</text>`);
  });
  parts.push('</svg>');
  return parts.join('\n');
}
