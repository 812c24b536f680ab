// The plots: one uPlot chart per integral, one curve per run, log-scale errors against time.
// Curves are redrawn from the Result on each animation frame while the stream runs. Errors
// below FLOOR are drawn on a dashed floor line with a note (see series.js), never at -∞.

import uPlot from 'uplot';
import { FLOOR, displaySeries } from './series.js';
import { el } from './dom.js';

const COLORS = ['#2563eb', '#dc2626', '#16a34a', '#9333ea', '#ea580c', '#0891b2', '#ca8a04', '#db2777', '#475569', '#65a30d'];

/** The colour of run `i` (the runs table uses it too). */
export function runColor(i) {
  return COLORS[i % COLORS.length];
}

/** The line width of run `i`: earlier runs are wider, so a curve hidden under a later identical
 * one (two methods can coincide on a system) still shows as a halo. */
export function runWidth(i) {
  return Math.max(1.25, 2.8 - 0.35 * i);
}

const INTEGRALS = {
  energy: ['Energy H', '|H(t) − H(0)|'],
  passenger_energy: ['Passenger energy E', '|E(t) − E(0)|'],
  driver_energy: ['Driver energy h', '|h(t) − h(0)|'],
  latitude: ['Latitude ℓ', '|ℓ − ℓ(0)| at the section crossings'],
  constraint: ['Constraint residual', '|A(q) q̇|'],
};

const HEIGHT = 300;

const DECADES = Array.from({ length: 617 }, (_, i) => 10 ** (i - 308));

export class Plots {
  /** `caption(scene)`: a line under each chart's title naming the scene (none without it). */
  constructor(container, { caption } = {}) {
    this.container = container;
    this.caption = caption;
    this.charts = [];
    new ResizeObserver(() => this.#resize()).observe(container);
  }

  /** Replaces the charts by empty ones for a new result. */
  reset(result) {
    this.destroy();
    this.result = result;
    for (const integral of result.scene.integrals ?? []) {
      const [title, subtitle] = INTEGRALS[integral] ?? [integral, 'error'];
      const card = el('section', 'plot-card');
      card.dataset.integral = integral;
      const head = el('header', 'plot-head');
      const sub = el('span', 'plot-sub', subtitle);
      head.append(el('h3', '', title), sub);
      const target = el('div', 'plot');
      const note = el('p', 'floor-note');
      note.hidden = true;
      note.textContent = `Values below ${FLOOR.toExponential(0)} are shown at ${FLOOR.toExponential(0)} on the dashed line (exact within round-off).`;
      card.append(head);
      if (this.caption) card.append(el('p', 'plot-scene', this.caption(result.scene)));
      card.append(target, note);
      this.container.append(card);
      const chart = { integral, card, note, sub, subtitle, clamped: false, u: null };
      chart.u = new uPlot(this.#options(result, chart), emptyData(result.runs.length), target);
      card.uplot = chart.u; // for the browser test: the drawn series
      this.charts.push(chart);
    }
  }

  /** Redraws every chart from the result (`view`: {stat, window}). */
  update(view) {
    if (!this.result) return;
    for (const chart of this.charts) {
      const tables = this.result.runs.map((run) => {
        const s = run.series[chart.integral] ?? { t: [], mean: [], max: [] };
        const d = displaySeries(s, view);
        chart.clamped ||= d.clamped;
        return [d.t, d.y];
      });
      // The time axis spans the whole run from the start, so the curves grow across it.
      const t_end = this.result.scene.t_end;
      if (Number.isFinite(t_end)) tables.push([[0, t_end]]);
      const data = uPlot.join(tables);
      chart.note.hidden = !chart.clamped;
      // Say what is drawn: the plain per-bucket statistic or a smoothed one.
      const how = [view.stat === 'max' ? 'max per bucket' : 'mean per bucket', view.window > 0 ? `running mean over ${view.window} time units` : ''];
      chart.sub.textContent = `${chart.subtitle} · ${how.filter(Boolean).join(', ')}`;
      chart.u.setData(data);
    }
    this.#labels();
  }

  /** Clears the floor flags (a new view may clamp differently). */
  resetFloor() {
    for (const chart of this.charts) chart.clamped = false;
  }

  destroy() {
    for (const chart of this.charts) {
      chart.u.destroy();
      chart.card.remove();
    }
    this.charts = [];
    this.result = null;
  }

  // Legend labels follow the run status: a failed run says so in every legend.
  #labels() {
    for (const chart of this.charts) {
      const rows = chart.u.root.querySelectorAll('.u-legend .u-series');
      this.result.runs.forEach((run, i) => {
        const row = rows[i + 1];
        if (!row) return;
        const label = row.querySelector('.u-label');
        const text = run.status === 'failed' ? `${run.label} (failed)` : run.label;
        if (label && label.textContent !== text) label.textContent = text;
        row.classList.toggle('failed', run.status === 'failed');
      });
    }
  }

  #options(result, chart) {
    return {
      width: this.#width(),
      height: HEIGHT,
      scales: {
        x: { time: false },
        y: { distr: 3, log: 10, range: (u, min, max) => logRange(min, max, chart.clamped) },
      },
      axes: [
        { label: 't', stroke: '#475569', grid: { stroke: '#e2e8f0' }, ticks: { stroke: '#cbd5e1' } },
        {
          label: 'error',
          stroke: '#475569',
          size: 64,
          grid: { stroke: '#e2e8f0' },
          ticks: { stroke: '#cbd5e1' },
          // uPlot's default log increments stop at 10^±16; a diverging run goes far beyond,
          // and without an increment the axis would lose its ticks.
          incrs: DECADES,
          splits: (u, axis, min, max) => decades(min, max, u.bbox.height / devicePixelRatio || HEIGHT),
          // uPlot's log filter would blank ticks that are not 1·, 2·, 5·10ⁿ; ours are all decades.
          filter: (u, splits) => splits,
          values: (u, splits) => splits.map(power),
        },
      ],
      series: [
        { label: 't', value: (u, v) => (v === null || v === undefined ? '–' : v.toPrecision(6)) },
        ...result.runs.map((run, i) => ({
          label: run.label,
          stroke: runColor(i),
          width: runWidth(i),
          points: { show: false },
          value: (u, v) => (v === null || v === undefined ? '–' : v.toExponential(3)),
        })),
      ],
      legend: { live: true },
      cursor: { drag: { x: true, y: false } },
      hooks: { draw: [(u) => drawFloor(u, chart)] },
    };
  }

  #width() {
    return Math.max(320, Math.floor(this.container.clientWidth - 34));
  }

  #resize() {
    const width = this.#width();
    for (const chart of this.charts) chart.u.setSize({ width, height: HEIGHT });
  }
}

function emptyData(runs) {
  return [[], ...Array.from({ length: runs }, () => [])];
}

// Whole decades around the data, one decade below the floor when the floor is in use so its
// line stays visible above the axis.
function logRange(min, max, clamped) {
  if (!(min > 0) || !(max > 0)) return [FLOOR / 10, 1];
  let lo = 10 ** Math.floor(Math.log10(min) + 1e-9);
  let hi = 10 ** Math.ceil(Math.log10(max) - 1e-9);
  if (clamped || min <= FLOOR) lo = Math.min(lo, FLOOR / 10);
  if (hi <= lo) hi = lo * 10;
  return [lo, hi];
}

// Ticks at whole decades only, thinned so labels stay ~28 px apart on a tall range.
function decades(min, max, height) {
  const lo = Math.ceil(Math.log10(min) - 1e-9);
  const hi = Math.floor(Math.log10(max) + 1e-9);
  const stride = Math.max(1, Math.ceil((28 * (hi - lo + 1)) / Math.max(height, 1)));
  const out = [];
  // Multiples of the stride, so 1 = 10⁰ is always a tick when in range.
  for (let e = Math.floor(hi / stride) * stride; e >= lo; e -= stride) out.unshift(10 ** e);
  return out;
}

const SUPERSCRIPT = { '-': '⁻', 0: '⁰', 1: '¹', 2: '²', 3: '³', 4: '⁴', 5: '⁵', 6: '⁶', 7: '⁷', 8: '⁸', 9: '⁹' };

// 1e-12 → "10⁻¹²"; 1 and 10 as themselves.
function power(v) {
  const e = Math.round(Math.log10(v));
  if (e === 0) return '1';
  if (e === 1) return '10';
  return `10${String(e).replace(/./g, (c) => SUPERSCRIPT[c])}`;
}

function drawFloor(u, chart) {
  if (!chart.clamped) return;
  const y = Math.round(u.valToPos(FLOOR, 'y', true));
  const { left, width } = u.bbox;
  const ctx = u.ctx;
  ctx.save();
  ctx.strokeStyle = '#64748b';
  ctx.lineWidth = devicePixelRatio;
  ctx.setLineDash([6 * devicePixelRatio, 4 * devicePixelRatio]);
  ctx.beginPath();
  ctx.moveTo(left, y);
  ctx.lineTo(left + width, y);
  ctx.stroke();
  ctx.setLineDash([]);
  ctx.fillStyle = '#64748b';
  ctx.font = `${11 * devicePixelRatio}px system-ui, sans-serif`;
  ctx.textAlign = 'right';
  ctx.fillText('round-off floor', left + width - 4 * devicePixelRatio, y - 4 * devicePixelRatio);
  ctx.restore();
}
