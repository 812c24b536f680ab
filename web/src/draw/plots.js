// The plots: one uPlot chart per integral, one curve per run, log-scale errors against time.
// Curves are redrawn from the Result on each animation frame while the stream runs. Errors
// below FLOOR are drawn on a dashed floor line with a note (see series.js), never at -∞.
// The y-range leaves out runs that diverged (axes.js) and says so; panels compared side by
// side can share one y-range (a `group`). Each card names its scene, exports PNG and SVG
// (export.js) and carries a text summary of its curves for screen readers (alttext.js).
// Each curve has its method's colour, dash and markers (palette.js), and its legend entry
// the run's verdict on the plot's integral (verdictbadge.js).

import uPlot from 'uplot';
import { FLOOR, displaySeries } from '../data/series.js';
import { el } from './dom.js';
import { clipRange, compactTick, decades, logRange, power, unionExtent } from './axes.js';
import { curveText, plotSummary } from './alttext.js';
import { exportButtons, withTicks } from './export.js';
import { humanLabel } from '../data/labels.js';
import { methodStyle } from './palette.js';
import { legendSwatches, seriesStyle } from './markers.js';
import { legendVerdict } from './verdictbadge.js';

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
  /** `caption(scene)`: a line under each chart's title naming the scene (none without it);
   *  `label(run)`: a curve's label (the run's, for people, by default); `stem(scene)`: the
   *  exported file name's start; `group`: a `{extents: Map}` shared by plots drawn on one
   *  y-range (its `members`, a Set of these plots, are redrawn when one changes its range;
   *  `key`, the range they are drawn on);
   *  `catalog`: GET /systems, for each method's colour and marker (palette.js). */
  constructor(container, { caption, label, stem, group, catalog } = {}) {
    this.container = container;
    this.caption = caption;
    this.catalog = catalog ?? null;
    this.label = label ?? ((run) => humanLabel(run.label));
    this.stem = stem ?? (() => 'nhlab');
    this.group = group ?? null;
    if (this.group) (this.group.members ??= new Set()).add(this);
    this.charts = [];
    new ResizeObserver(() => this.#resize()).observe(container);
  }

  /** Replaces the charts by empty ones for a new result. */
  reset(result) {
    this.destroy();
    this.result = result;
    for (const integral of result.scene.integrals ?? []) {
      // A named invariant of the system (its name as the system gives it).
      const [title, subtitle] = INTEGRALS[integral] ?? [`Invariant ${integral}`, `|${integral}(t) − ${integral}(0)|`];
      const card = el('section', 'plot-card');
      card.dataset.integral = integral;
      const head = el('header', 'plot-head');
      const sub = el('span', 'plot-sub', subtitle);
      head.append(el('h3', '', title), sub);
      const target = el('div', 'plot');
      const note = el('p', 'floor-note');
      note.hidden = true;
      note.textContent = `Values below ${FLOOR.toExponential(0)} are shown at ${FLOOR.toExponential(0)} on the dashed line (exact within round-off).`;
      const scene = this.caption ? this.caption(result.scene) : '';
      card.append(head);
      if (scene) card.append(el('p', 'plot-scene', scene));
      const clip = el('p', 'clip-note');
      clip.hidden = true;
      const alt = el('p', 'sr-only plot-alt');
      // Curves that stop while their run goes on: from when and why (the series' gap).
      const gaps = el('p', 'gap-note');
      gaps.hidden = true;
      const foot = el('div', 'plot-foot');
      card.append(target, note, clip, gaps, foot, alt);
      this.container.append(card);
      const chart = { integral, card, note, clip, gaps, alt, sub, subtitle, title, scene, clamped: false, full: false, extent: null, u: null };
      chart.u = new uPlot(this.#options(result, chart), emptyData(result.runs.length), target);
      chart.u.ctx.canvas.setAttribute('role', 'img');
      legendSwatches(chart.u, result.runs.map((run) => methodStyle(this.catalog, run.method)));
      card.uplot = chart.u; // for the browser test: the drawn series
      foot.append(exportButtons(() => chart.u, () => ({ title: `${title} error`, caption: scene, stem: `${this.stem(result.scene)}-${integral}`, styles: result.runs.map((run) => methodStyle(this.catalog, run.method)), floor: chart.clamped ? FLOOR : null })));
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
      this.#range(chart, tables.slice(0, this.result.runs.length).map(([, y]) => y));
      chart.note.hidden = !chart.clamped;
      const gaps = this.result.runs.filter((run) => run.gaps?.[chart.integral]).map((run) => `${this.label(run)}: ${run.gaps[chart.integral].message}.`);
      chart.gaps.textContent = gaps.join(' ');
      chart.gaps.hidden = gaps.length === 0;
      // Say what is drawn: the plain per-bucket statistic or a smoothed one.
      const how = [view.stat === 'max' ? 'max per bucket' : 'mean per bucket', view.window > 0 ? `running mean over ${view.window} time units` : ''];
      chart.sub.textContent = `${chart.subtitle} · ${how.filter(Boolean).join(', ')}`;
      chart.u.setData(data);
      this.#summary(chart, tables);
    }
    this.#labels();
    // The group's y-range grew: its other members redraw on it.
    if (!this.group) return;
    const key = JSON.stringify(unionExtent([...this.group.extents.values()]));
    if (key === this.group.key) return;
    this.group.key = key;
    for (const plots of this.group.members) if (plots !== this) plots.refresh();
  }

  // The y extent without the runs that diverged, shared with the group; a note names them.
  // "Show the full range" holds for the whole group (panels compared side by side).
  #range(chart, ys) {
    chart.ys = ys;
    const showFull = this.group ? Boolean(this.group.full) : Boolean(chart.full);
    const { range, full, clipped } = clipRange(ys);
    chart.extent = showFull ? full : range;
    if (this.group) this.group.extents.set(chart, chart.extent);
    chart.clip.hidden = clipped.length === 0;
    if (!clipped.length) return;
    const key = `${showFull}|${clipped.map((c) => `${c.index}:${c.max.toExponential(1)}`).join(',')}`;
    if (chart.clip.dataset.key === key) return;
    chart.clip.dataset.key = key;
    const names = clipped.map((c) => `${this.label(this.result.runs[c.index])} (up to ${c.max.toExponential(1)})`).join(', ');
    const toggle = el('button', 'link-button', showFull ? 'Clip to the other runs' : 'Show the full range');
    toggle.type = 'button';
    toggle.addEventListener('click', () => {
      if (this.group) this.group.full = !showFull;
      else chart.full = !showFull;
      const members = [...(this.group?.members ?? [this])];
      // Every range first, then every redraw: a group's charts share the union of them.
      for (const plots of members) plots.#rerange();
      for (const plots of members) plots.refresh();
    });
    const one = clipped.length === 1;
    const what = showFull ? `Full range shown, including ${names}.` : `The y-axis is clipped: ${names} ${one ? 'diverges, and its curve leaves' : 'diverge, and their curves leave'} the plot.`;
    chart.clip.replaceChildren(what, ' ', toggle);
  }

  // Recomputes every chart's range and note (`refresh` redraws them).
  #rerange() {
    for (const chart of this.charts) {
      if (!chart.ys) continue;
      this.#range(chart, chart.ys);
    }
  }

  /** The y-range of a chart: its own extent, or its group's. */
  #yRange(chart) {
    return this.group ? unionExtent([...this.group.extents.values()]) : chart.extent;
  }

  /** Redraws the charts on the group's current y-range (after another panel's update). */
  refresh() {
    for (const chart of this.charts) chart.u.setData(chart.u.data);
  }

  // The text alternative: each curve's last error and verdict (or status).
  #summary(chart, tables) {
    const items = this.result.runs.map((run, i) => ({
      label: this.label(run),
      text: curveText(tables[i][1], { verdict: run.verdicts?.[chart.integral]?.kind ?? null, status: run.status }),
    }));
    const text = plotSummary(`${chart.title} error against t`, chart.scene, items);
    if (chart.alt.textContent !== text) {
      chart.alt.textContent = text;
      chart.u.ctx.canvas.setAttribute('aria-label', text);
    }
  }

  /** Clears the floor flags (a new view may clamp differently). */
  resetFloor() {
    for (const chart of this.charts) chart.clamped = false;
  }

  destroy() {
    for (const chart of this.charts) {
      this.group?.extents.delete(chart);
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
        const text = run.status === 'failed' ? `${this.label(run)} (failed)` : this.label(run);
        if (label && label.textContent !== text) label.textContent = text;
        row.classList.toggle('failed', run.status === 'failed');
        legendVerdict(row, run, chart.integral);
      });
    }
  }

  #options(result, chart) {
    return {
      width: this.#width(),
      height: HEIGHT,
      scales: {
        x: { time: false },
        y: {
          distr: 3,
          log: 10,
          range: (u, min, max) => {
            const e = this.#yRange(chart);
            return e ? logRange(e[0], e[1], chart.clamped) : logRange(min, max, chart.clamped);
          },
        },
      },
      axes: [
        // Compact labels (3e6, not 3,000,000) and room for them, so long times do not overlap.
        { label: 't', stroke: '#475569', grid: { stroke: '#e2e8f0' }, ticks: { stroke: '#cbd5e1' }, space: 60, values: (u, splits) => splits.map(compactTick) },
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
          ...seriesStyle(methodStyle(this.catalog, run.method), { width: runWidth(i) }),
          label: this.label(run),
          value: (u, v) => (v === null || v === undefined ? '–' : v.toExponential(3)),
        })),
      ],
      legend: { live: true },
      plugins: [withTicks()],
      cursor: { drag: { x: true, y: false } },
      hooks: { draw: [(u) => drawFloor(u, chart)] },
    };
  }

  #width() {
    return Math.max(240, Math.floor(this.container.clientWidth - 34));
  }

  #resize() {
    const width = this.#width();
    for (const chart of this.charts) chart.u.setSize({ width, height: HEIGHT });
  }
}

function emptyData(runs) {
  return [[], ...Array.from({ length: runs }, () => [])];
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
