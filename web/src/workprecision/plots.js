// The Work–precision view's drawing: two log–log plot cards for an answer of
// `POST /work-precision` (final error against run time, or run time against final error as
// DiffEqDevTools draws it; final error against h), each naming the scene it measured, with
// PNG/SVG export and a text summary, and the table of fitted orders and final errors.

import uPlot from 'uplot';
import { runWidth } from '../draw/plots.js';
import { methodStyle } from '../draw/palette.js';
import { legendSwatches, seriesStyle, swatch } from '../draw/markers.js';
import { curves, distinctX, formatOrder } from './precision.js';
import { humanLabel } from '../data/labels.js';
import { plotSummary, sci } from '../draw/alttext.js';
import { exportButtons, withTicks } from '../draw/export.js';
import { el } from '../draw/dom.js';
import { compactTick } from '../draw/axes.js';

export const HEIGHT = 320;

const TIME = 'run time (ms, fastest of the repeats)';
const ERROR = 'final error ‖(q, q̇) − reference‖∞';

/** The two plots for an orientation of the time plot: `{key, title, x, y, swap}`. */
export function plotSpecs(orient) {
  const swap = orient === 'error-x';
  return [
    swap
      ? { key: 'time', title: 'Run time against final error', x: ERROR, y: TIME, swap }
      : { key: 'time', title: 'Final error against run time', x: TIME, y: ERROR, swap },
    { key: 'step', title: 'Final error against step h', x: 'h', y: ERROR, swap: false },
  ];
}

/**
 * Draws an answer into `plots` and `table`: returns the charts (`{card, u}`). `scene`: the
 * scene's caption; `stem`: the file-name start; `width`: the charts' width; `catalog`: GET
 * /systems, for each method's colour and marker (palette.js).
 */
export function renderAnswer(answer, { plots, table, orient, scene, stem, width, catalog }) {
  const cs = curves(answer);
  const styles = cs.map((c) => methodStyle(catalog, c.method));
  const charts = plotSpecs(orient).map((p) => {
    const card = el('section', 'plot-card wp-card');
    card.dataset.plot = p.key;
    card.dataset.orient = p.key === 'time' ? orient : 'h';
    const head = el('header', 'plot-head');
    head.append(el('h3', '', p.title), el('span', 'plot-sub', `log–log; x: ${p.x}`));
    const caption = el('p', 'plot-scene wp-scene', scene);
    const target = el('div', 'plot');
    const foot = el('div', 'plot-foot');
    const alt = el('p', 'sr-only plot-alt');
    card.append(head, caption, target, foot, alt);
    const pairs = (c) => distinctX(p.swap ? c.time.map(([t, e]) => [e, t]).sort((a, b) => a[0] - b[0]) : c[p.key]);
    const data = uPlot.join(cs.map(pairs).map((xy) => [xy.map(([x]) => x), xy.map(([, y]) => y)]));
    const u = new uPlot(options(cs, p, width, styles), cs.length ? data : [[]], target);
    legendSwatches(u, styles);
    card.uplot = u; // for the browser test: the drawn series
    const text = plotSummary(p.title, scene, cs.map((c) => ({ label: humanLabel(c.label), text: curveText(c, p.key) })));
    alt.textContent = text;
    u.ctx.canvas.setAttribute('role', 'img');
    u.ctx.canvas.setAttribute('aria-label', text);
    foot.append(exportButtons(() => u, () => ({ title: p.title, caption: scene, styles, stem: `${stem}-work-precision-${p.key === 'time' ? (p.swap ? 'time-vs-error' : 'error-vs-time') : 'error-vs-h'}` })));
    return { card, u };
  });
  plots.replaceChildren(...charts.map((c) => c.card));
  table.replaceChildren(orderTable(cs, answer, styles));
  return charts;
}

// A curve's summary: its smallest final error, its order on the h plot, its failures.
function curveText(c, key) {
  const errors = c.step.map(([, e]) => e);
  const parts = [`smallest final error ${sci(errors.length ? Math.min(...errors) : null)}`];
  if (key === 'step') parts.push(`order ${formatOrder(c.order)}`);
  if (c.failed.length) parts.push(`${c.failed.length} failed`);
  return parts.join(', ');
}

function options(cs, plot, width, styles) {
  const axis = (label) => ({ label, stroke: '#475569', grid: { stroke: '#e2e8f0' }, ticks: { stroke: '#cbd5e1' }, values: (u, splits) => splits.map(compactTick) });
  return {
    width,
    height: HEIGHT,
    scales: { x: { time: false, distr: 3, log: 10, range: decadeRange }, y: { distr: 3, log: 10, range: decadeRange } },
    axes: [axis(plot.x), { ...axis(plot.y), size: 70 }],
    series: [
      { label: plot.x },
      ...cs.map((c, i) => ({
        // Every point marked, in the method's shape; points shrink with i as the lines do
        // (runWidth), for the same halo.
        ...seriesStyle(styles[i], { width: runWidth(i), size: Math.max(6, 11 - i), sparse: false }),
        label: legendLabel(c, plot.key),
        spanGaps: true,
      })),
    ],
    legend: { live: false },
    plugins: [withTicks()],
  };
}

// Per method: the fitted order, then each step's final error (or "failed" with the reason).
function orderTable(cs, answer, styles) {
  const steps = [...new Set(answer.rows.map((r) => r.step))];
  const table = el('table', 'runs wp-orders');
  const head = el('tr');
  head.append(el('th', '', 'Method'), el('th', 'num', 'Order (slope vs h)'));
  for (const h of steps) head.append(el('th', 'num', `h = ${compactTick(h)}`));
  const thead = el('thead');
  thead.append(head);
  const tbody = el('tbody');
  cs.forEach((c, i) => {
    const tr = el('tr', 'wp-method');
    tr.dataset.method = c.label;
    const name = el('th');
    name.append(swatch(styles[i]), humanLabel(c.label));
    const order = el('td', 'num slope', formatOrder(c.order));
    order.dataset.order = c.order ?? '';
    tr.append(name, order);
    for (const h of steps) {
      const row = c.rows.find((r) => r.step === h);
      if (!row) tr.append(el('td', 'num', ''));
      else if (row.status !== 'ok') {
        const td = el('td', 'num');
        const badge = el('span', 'badge failed', 'failed');
        badge.title = row.error ?? 'failed';
        td.append(badge);
        td.classList.add('failed');
        tr.append(td);
      } else {
        const td = el('td', 'num', row.final_error > 0 ? row.final_error.toExponential(2) : String(row.final_error));
        td.title = `${row.steps} steps, ${row.elapsed_ms} ms`;
        tr.append(td);
      }
    }
    tbody.append(tr);
  });
  table.append(thead, tbody);
  // Every failure with the server's message, so none is silent.
  const failures = el('ul', 'wp-failures');
  for (const c of cs) {
    for (const r of c.failed) failures.append(el('li', '', `${humanLabel(c.label)} at h = ${compactTick(r.step)} failed: ${r.error ?? 'no message'}`));
  }
  const wrap = el('div');
  wrap.append(table);
  if (failures.children.length) wrap.append(failures);
  return wrap;
}

/** Whole decades around the data (one more on each side of a single value). */
function decadeRange(u, min, max) {
  if (!(min > 0) || !(max > 0)) return [1e-3, 1];
  const lo = Math.floor(Math.log10(min) + 1e-9);
  let hi = Math.ceil(Math.log10(max) - 1e-9);
  if (hi <= lo) return [10 ** (lo - 1), 10 ** (lo + 1)];
  return [10 ** lo, 10 ** hi];
}

/** A legend entry: the label, the fitted order on the h plot, the failures on both. */
function legendLabel(c, key) {
  const parts = [];
  if (key === 'step') parts.push(`order ${formatOrder(c.order)}`);
  if (c.failed.length) parts.push(`${c.failed.length} failed`);
  const label = humanLabel(c.label);
  return parts.length ? `${label} (${parts.join(', ')})` : label;
}
