// The heat map of the Map view, drawn on a canvas: a grid of cells (x along the last axis, y
// along the first, a single row for one axis), each coloured by its verdict (with the
// verdict's letter, so colour is not needed to read it) or by log₁₀ of its largest error
// against a colour bar. Cells not yet computed are pale, failed ones dark with a cross,
// invalid ones hatched. Hovering a cell outlines it and shows its tooltip; clicking it (or
// Enter on the focused canvas, arrows moving between cells) calls `onOpen(cell)`. The colour
// functions are pure, so node tests cover them.

import { FLOOR } from '../data/series.js';
import { VERDICTS } from '../data/verdicts.js';
import { el } from '../draw/dom.js';
import { powerOfTen } from '../draw/axes.js';

/** Fill colours of the verdicts and of the cells that have none. */
export const KIND_COLORS = {
  exact: '#15803d',
  bounded: '#2563eb',
  drift: '#dc2626',
  none: '#cbd5e1',
  pending: '#f1f5f9',
  failed: '#64748b',
  invalid: '#ffffff',
};

/** The marks drawn on a cell (besides the colour): verdict letters, failed and invalid signs. */
export const KIND_MARKS = {
  ...Object.fromEntries(VERDICTS.map((v) => [v.kind, v.letter])),
  none: '–',
  failed: '✕',
  invalid: '⊘',
};

/** The kinds of cell besides the verdicts, as the keys name them: short (an exported
 *  picture's key line) and long (the page's legend). */
export const OTHER_KINDS = [
  { kind: 'none', short: 'no value', long: 'no verdict' },
  { kind: 'failed', short: 'failed', long: 'run failed' },
  { kind: 'invalid', short: 'invalid', long: 'invalid here (the values make the scene or method invalid)' },
];

/** Errors below this are coloured as it (exact to round-off, or exactly 0): the plots' floor. */
export const LOG_FLOOR = FLOOR;

// Viridis, sampled: dark purple for the smallest errors to yellow for the largest.
const VIRIDIS = ['#440154', '#482878', '#3e4989', '#31688e', '#26828e', '#1f9e89', '#35b779', '#6ece58', '#b5de2b', '#fde725'];

/** The colour at t ∈ [0, 1] of the log scale (clamped), interpolated between samples. */
export function viridis(t) {
  const x = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0)) * (VIRIDIS.length - 1);
  const i = Math.min(VIRIDIS.length - 2, Math.floor(x));
  const [a, b] = [VIRIDIS[i], VIRIDIS[i + 1]].map(rgb);
  const f = x - i;
  return `#${a.map((v, k) => Math.round(v + (b[k] - v) * f).toString(16).padStart(2, '0')).join('')}`;
}

/** log₁₀ of an error, lifted to the floor. */
export function logError(max) {
  return Math.log10(Math.max(max, LOG_FLOOR));
}

/** The colour bar's range: whole decades around the errors given (one decade at least). */
export function decadeRange(maxima) {
  const logs = maxima.filter((m) => typeof m === 'number' && Number.isFinite(m)).map(logError);
  if (!logs.length) return [-16, 0];
  const lo = Math.floor(Math.min(...logs) + 1e-9) + 0; // + 0: no −0
  const hi = Math.ceil(Math.max(...logs) - 1e-9) + 0;
  return hi > lo ? [lo, hi] : [lo, lo + 1];
}

/** A cell's fill: its kind's colour, or for a largest error in log mode its place on the bar. */
export function cellColor({ kind, max }, mode, range) {
  if (mode === 'log' && ['exact', 'bounded', 'drift'].includes(kind) && typeof max === 'number') {
    return viridis((logError(max) - range[0]) / (range[1] - range[0]));
  }
  return KIND_COLORS[kind] ?? KIND_COLORS.none;
}

/** Every `step`-th tick, so that labels at least `minPx` apart fit `n` cells over `px`. */
export function tickStep(n, px, minPx) {
  return Math.max(1, Math.ceil((n * minPx) / Math.max(px, 1)));
}

function rgb(hex) {
  return [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
}

const MARGIN = { top: 10, bottom: 48, left: 84, right: 16, bar: 92 };

export class Heatmap {
  /** `onOpen(cell)`: a cell clicked; `format(v)`: tick labels. */
  constructor(container, { onOpen, format }) {
    this.onOpen = onOpen;
    this.format = format;
    this.model = null;
    this.hover = null;
    this.drawn = 0;
    this.wrap = el('div', 'heatmap');
    this.canvas = el('canvas', 'heatmap-canvas');
    this.canvas.tabIndex = 0;
    this.canvas.setAttribute('role', 'img');
    this.canvas.heatmap = this; // for the browser test: cells drawn, where each cell is
    this.tooltip = el('div', 'map-tooltip');
    this.tooltip.setAttribute('role', 'tooltip');
    this.tooltip.hidden = true;
    this.wrap.append(this.canvas, this.tooltip);
    container.append(this.wrap);
    this.#wire();
    new ResizeObserver(() => this.draw()).observe(this.wrap);
  }

  /**
   * What to draw: `xs`, `ys` (null for one axis) and their titles, `cells`, `stateOf(cell)`
   * ({kind, max}), `linesOf(cell)` (tooltip lines), `cellAt(x, y)`, `xyOf(cell)`, `mode`.
   */
  set(model) {
    this.model = model;
    this.canvas.setAttribute('aria-label', model.label ?? 'heat map');
    this.draw();
    if (this.hover !== null) this.#showTooltip(this.hover, this.lastPointer);
  }

  /** The layout in CSS pixels for the current width. */
  layout() {
    const m = this.model;
    const width = Math.max(320, this.wrap.clientWidth || 800);
    const ny = m.ys ? m.ys.length : 1;
    const left = m.ys ? MARGIN.left : 16;
    const right = m.mode === 'log' ? MARGIN.bar : MARGIN.right;
    const pw = width - left - right;
    const ph = m.ys ? Math.min(480, Math.max(140, ny * 28)) : 56;
    return { width, height: MARGIN.top + ph + MARGIN.bottom, left, top: MARGIN.top, pw, ph, cw: pw / m.xs.length, ch: ph / ny, ny };
  }

  /** A cell's rectangle (CSS pixels, relative to the canvas) in layout `L`. */
  rectOf(cell, L = this.layout()) {
    const { x, y } = this.model.xyOf(cell);
    return { x: L.left + x * L.cw, y: L.top + (L.ny - 1 - y) * L.ch, w: L.cw, h: L.ch };
  }

  /** A cell's centre (CSS pixels, relative to the canvas), for the browser test. */
  centerOf(cell) {
    const r = this.rectOf(cell);
    return { x: r.x + r.w / 2, y: r.y + r.h / 2 };
  }

  draw() {
    const m = this.model;
    if (!m || !m.xs.length) return;
    const L = this.layout();
    const dpr = window.devicePixelRatio || 1;
    this.canvas.width = Math.round(L.width * dpr);
    this.canvas.height = Math.round(L.height * dpr);
    this.canvas.style.width = `${L.width}px`;
    this.canvas.style.height = `${L.height}px`;
    const ctx = this.canvas.getContext('2d');
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, L.width, L.height);
    this.paint(ctx, L);
    if (this.hover !== null && this.hover < m.cells) {
      const r = this.rectOf(this.hover, L);
      ctx.strokeStyle = '#0f172a';
      ctx.lineWidth = 2;
      ctx.strokeRect(r.x + 1, r.y + 1, Math.max(1, r.w - 3), Math.max(1, r.h - 3));
    }
  }

  /** Draws the cells, axes and colour bar with layout `L` on `ctx` (a canvas context, or an
   *  SvgContext for a vector file). */
  paint(ctx, L) {
    const m = this.model;
    const states = Array.from({ length: m.cells }, (_, c) => m.stateOf(c));
    const range = decadeRange(states.map((s) => s.max));
    this.range = range;
    this.drawn = 0;
    ctx.textAlign = 'center';
    ctx.textBaseline = 'middle';
    ctx.font = '600 11px system-ui, sans-serif';
    const letters = L.cw >= 13 && L.ch >= 13;
    states.forEach((s, c) => {
      const r = this.rectOf(c, L);
      const gap = L.cw > 4 && L.ch > 4 ? 1 : 0;
      ctx.fillStyle = cellColor(s, m.mode, range);
      ctx.fillRect(r.x, r.y, r.w - gap, r.h - gap);
      if (s.kind !== 'pending') this.drawn++;
      if (s.kind === 'invalid') hatch(ctx, r, gap);
      const mark = m.mode === 'log' && !['failed', 'invalid', 'none'].includes(s.kind) ? '' : KIND_MARKS[s.kind];
      if (letters && mark) {
        ctx.fillStyle = s.kind === 'invalid' || s.kind === 'none' ? '#475569' : '#ffffff';
        ctx.fillText(mark, r.x + (r.w - gap) / 2, r.y + (r.h - gap) / 2 + 0.5);
      }
    });
    this.#axes(ctx, L);
    if (m.mode === 'log') this.#colorBar(ctx, L, range);
  }

  #axes(ctx, L) {
    const m = this.model;
    ctx.fillStyle = '#475569';
    ctx.font = '11.5px system-ui, sans-serif';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'top';
    const sx = tickStep(m.xs.length, L.pw, 52);
    m.xs.forEach((v, i) => {
      if (i % sx === 0) ctx.fillText(this.format(v), L.left + (i + 0.5) * L.cw, L.top + L.ph + 5);
    });
    ctx.font = '600 12.5px system-ui, sans-serif';
    ctx.fillStyle = '#0f172a';
    ctx.fillText(m.xTitle, L.left + L.pw / 2, L.top + L.ph + 26);
    if (!m.ys) return;
    ctx.font = '11.5px system-ui, sans-serif';
    ctx.fillStyle = '#475569';
    ctx.textAlign = 'right';
    ctx.textBaseline = 'middle';
    const sy = tickStep(m.ys.length, L.ph, 16);
    m.ys.forEach((v, i) => {
      if (i % sy === 0) ctx.fillText(this.format(v), L.left - 6, L.top + (L.ny - 1 - i + 0.5) * L.ch);
    });
    ctx.save();
    ctx.translate(14, L.top + L.ph / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.textAlign = 'center';
    ctx.font = '600 12.5px system-ui, sans-serif';
    ctx.fillStyle = '#0f172a';
    ctx.fillText(m.yTitle, 0, 0);
    ctx.restore();
  }

  #colorBar(ctx, L, [lo, hi]) {
    const x = L.left + L.pw + 16;
    const w = 14;
    const grad = ctx.createLinearGradient(0, L.top + L.ph, 0, L.top);
    for (let k = 0; k <= 10; k++) grad.addColorStop(k / 10, viridis(k / 10));
    ctx.fillStyle = grad;
    ctx.fillRect(x, L.top, w, L.ph);
    ctx.strokeStyle = '#94a3b8';
    ctx.lineWidth = 1;
    ctx.strokeRect(x + 0.5, L.top + 0.5, w - 1, L.ph - 1);
    ctx.fillStyle = '#475569';
    ctx.font = '11px system-ui, sans-serif';
    ctx.textAlign = 'left';
    ctx.textBaseline = 'middle';
    // At most eight labels, 13 px apart at least.
    const step = Math.max(1, Math.ceil((hi - lo) / 8), Math.ceil(((hi - lo) * 13) / L.ph));
    for (let k = lo; k <= hi; k += step) {
      const y = L.top + L.ph - ((k - lo) / (hi - lo)) * L.ph;
      ctx.fillRect(x + w, y - 0.5, 4, 1);
      ctx.fillText(powerOfTen(k), x + w + 7, y);
    }
    ctx.textBaseline = 'top';
    ctx.fillText('max error', x - 4, L.top + L.ph + 6);
  }

  #cellAtPointer(px, py) {
    const m = this.model;
    if (!m) return null;
    const L = this.layout();
    const x = Math.floor((px - L.left) / L.cw);
    const row = Math.floor((py - L.top) / L.ch);
    if (x < 0 || x >= m.xs.length || row < 0 || row >= L.ny) return null;
    return m.cellAt(x, L.ny - 1 - row);
  }

  #wire() {
    const c = this.canvas;
    c.addEventListener('pointermove', (e) => {
      this.lastPointer = { x: e.offsetX, y: e.offsetY };
      this.#setHover(this.#cellAtPointer(e.offsetX, e.offsetY), this.lastPointer);
    });
    c.addEventListener('pointerleave', () => this.#setHover(null));
    c.addEventListener('click', (e) => {
      const cell = this.#cellAtPointer(e.offsetX, e.offsetY);
      if (cell !== null) this.onOpen(cell);
    });
    c.addEventListener('blur', () => this.#setHover(null));
    c.addEventListener('keydown', (e) => {
      const m = this.model;
      if (!m) return;
      if (e.key === 'Enter' && this.hover !== null) {
        this.onOpen(this.hover);
        return;
      }
      if (e.key === 'Escape') return this.#setHover(null);
      const moves = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, 1], ArrowDown: [0, -1] };
      if (!moves[e.key]) return;
      e.preventDefault();
      const ny = m.ys ? m.ys.length : 1;
      const at = this.hover === null ? { x: 0, y: 0 } : m.xyOf(this.hover);
      const x = Math.min(m.xs.length - 1, Math.max(0, at.x + moves[e.key][0]));
      const y = Math.min(ny - 1, Math.max(0, at.y + moves[e.key][1]));
      const cell = m.cellAt(x, y);
      const center = this.centerOf(cell);
      this.lastPointer = center;
      this.#setHover(cell, center);
    });
  }

  #setHover(cell, at) {
    if (cell === this.hover && cell !== null) {
      this.#showTooltip(cell, at);
      return;
    }
    this.hover = cell;
    this.draw();
    if (cell === null) this.tooltip.hidden = true;
    else this.#showTooltip(cell, at);
  }

  #showTooltip(cell, at) {
    const lines = this.model.linesOf(cell);
    this.tooltip.replaceChildren(...lines.map((t, i) => el(i === 0 ? 'strong' : 'div', '', t)));
    this.tooltip.dataset.cell = cell;
    this.tooltip.hidden = false;
    const p = at ?? this.centerOf(cell);
    const w = this.tooltip.offsetWidth;
    const width = this.wrap.clientWidth;
    const x = p.x + 16 + w > width ? Math.max(0, p.x - 16 - w) : p.x + 16;
    this.tooltip.style.left = `${x}px`;
    this.tooltip.style.top = `${p.y + 16}px`;
  }
}

// Diagonal lines over an invalid cell.
function hatch(ctx, r, gap) {
  ctx.save();
  ctx.beginPath();
  ctx.rect(r.x, r.y, r.w - gap, r.h - gap);
  ctx.clip();
  ctx.strokeStyle = '#94a3b8';
  ctx.lineWidth = 1;
  for (let d = -r.h; d < r.w; d += 6) {
    ctx.moveTo(r.x + d, r.y + r.h);
    ctx.lineTo(r.x + d + r.h, r.y);
  }
  ctx.stroke();
  ctx.restore();
  ctx.strokeStyle = '#cbd5e1';
  ctx.strokeRect(r.x + 0.5, r.y + 0.5, r.w - gap - 1, r.h - gap - 1);
}
