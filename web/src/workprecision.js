// The Work–precision view: posts the form's scene and methods to `/work-precision` (the
// scene's step and `levels` halvings of it) and draws two log–log plots, final error against
// run time and final error against h, one line per method, with each method's fitted order
// (slope against h) in the legend and in a table beside the rows that failed. Its state is
// the form's plus `levels` and `repeats`, in the URL as `?view=work-precision&…`.

import uPlot from 'uplot';
import { ApiError, fetchWorkPrecision, retrying } from './api.js';
import { sceneCaption } from './custom.js';
import { runColor, runWidth } from './plots.js';
import { MAX_LEVELS, MAX_REPEATS, curves, decodeSettings, formatOrder, workPrecisionBody, workPrecisionQuery } from './precision.js';
import { el } from './dom.js';

const HEIGHT = 320;

const PLOTS = [
  { key: 'time', title: 'Final error against run time', x: 'run time (ms, fastest of the repeats)' },
  { key: 'step', title: 'Final error against step h', x: 'h' },
];

export class WorkPrecisionView {
  /** `read()`: the form's `{state, invalid}`; `catalog`: `GET /systems`. */
  constructor(root, { read, catalog }) {
    this.root = root;
    this.read = read;
    this.catalog = catalog;
    this.controller = null;
    this.charts = [];
    this.computedFor = null;
    this.status = root.querySelector('.view-status');
    this.plots = root.querySelector('.wp-plots');
    this.table = root.querySelector('.wp-table');
    this.levels = root.querySelector('.wp-levels');
    this.repeats = root.querySelector('.wp-repeats');
    const settings = decodeSettings(location.search);
    this.levels.value = settings.levels;
    this.repeats.value = settings.repeats;
    this.levels.max = MAX_LEVELS;
    this.repeats.max = MAX_REPEATS;
    root.querySelector('.wp-run').addEventListener('click', () => this.load());
    new ResizeObserver(() => this.#resize()).observe(this.plots);
  }

  /** Computes for the form's current scene, unless it is the one shown already. */
  show() {
    const { state } = this.read();
    const query = workPrecisionQuery(state, this.catalog, this.#settings());
    history.replaceState(null, '', `?${query}`);
    if (query !== this.computedFor && !this.controller) this.load();
  }

  #settings() {
    const int = (input, fallback, max) => {
      const v = Number(input.value);
      return Number.isInteger(v) ? Math.min(Math.max(v, 1), max) : fallback;
    };
    return { levels: int(this.levels, 4, MAX_LEVELS), repeats: int(this.repeats, 3, MAX_REPEATS) };
  }

  async load() {
    const { state, invalid } = this.read();
    if (invalid.length) {
      this.#status('error', `The form has errors (${invalid.map((e) => e.path).join(', ')}): fix them in Explore.`);
      return;
    }
    const settings = this.#settings();
    const query = workPrecisionQuery(state, this.catalog, settings);
    history.replaceState(null, '', `?${query}`);
    this.controller?.abort();
    const mine = new AbortController();
    this.controller = mine;
    const h = state.step;
    this.#status('running', `Measuring ${state.methods.length} methods at ${settings.levels} step sizes${h ? ` from h = ${h}` : ''}, ${settings.repeats} repeats each…`);
    try {
      const answer = await retrying(
        () => fetchWorkPrecision(workPrecisionBody(state, settings), { signal: mine.signal }),
        (wait) => this.#status('running', `The server is busy; retrying in ${wait} s…`),
      );
      if (this.controller !== mine) return;
      this.computedFor = query;
      this.render(answer);
      const failed = answer.rows.filter((r) => r.status !== 'ok').length;
      const ref = answer.reference;
      const refText = `reference: Dop853, ${ref.steps} steps${ref.cached ? ', cached' : `, ${ref.elapsed_ms.toFixed(1)} ms`}`;
      const scene = answer.scene ? ` on ${sceneCaption(answer.scene, this.catalog)}` : '';
      this.#status(failed ? 'done-failed' : 'done', `Done: ${answer.rows.length} runs${scene}${failed ? `, ${failed} failed (see the table)` : ''}; ${refText}.`);
    } catch (e) {
      if (this.controller !== mine || e.name === 'AbortError') return;
      const where = e instanceof ApiError && e.path ? ` (field ${e.path})` : '';
      this.#status('error', `Work–precision failed: ${e.message}${where}`);
    } finally {
      if (this.controller === mine) this.controller = null;
    }
  }

  render(answer) {
    const cs = curves(answer);
    this.answer = answer;
    for (const c of this.charts) c.u.destroy();
    this.charts = [];
    const cards = PLOTS.map((p) => {
      const card = el('section', 'plot-card wp-card');
      card.dataset.plot = p.key;
      const head = el('header', 'plot-head');
      head.append(el('h3', '', p.title), el('span', 'plot-sub', `log–log; x: ${p.x}`));
      const target = el('div', 'plot');
      card.append(head, target);
      const data = uPlot.join(cs.map((c) => [c[p.key].map(([x]) => x), c[p.key].map(([, y]) => y)]));
      const u = new uPlot(this.#options(cs, p), cs.length ? data : [[]], target);
      card.uplot = u; // for the browser test: the drawn series
      this.charts.push({ card, u });
      return card;
    });
    this.plots.replaceChildren(...cards);
    this.table.replaceChildren(this.#table(cs, answer));
  }

  #options(cs, plot) {
    const axis = (label) => ({ label, stroke: '#475569', grid: { stroke: '#e2e8f0' }, ticks: { stroke: '#cbd5e1' }, values: (u, splits) => splits.map(short) });
    return {
      width: this.#width(),
      height: HEIGHT,
      scales: { x: { time: false, distr: 3, log: 10, range: decadeRange }, y: { distr: 3, log: 10, range: decadeRange } },
      axes: [axis(plot.x), { ...axis('final error ‖(q, q̇) − reference‖∞'), size: 70 }],
      series: [
        { label: plot.x },
        ...cs.map((c, i) => ({
          label: legendLabel(c, plot.key),
          stroke: runColor(i),
          // Points shrink with i as the lines do (runWidth), for the same halo.
          width: runWidth(i),
          spanGaps: true,
          points: { show: true, size: Math.max(5, 11 - i), fill: runColor(i) },
        })),
      ],
      legend: { live: false },
    };
  }

  // Per method: the fitted order, then each step's final error (or "failed" with the reason).
  #table(cs, answer) {
    const steps = [...new Set(answer.rows.map((r) => r.step))];
    const table = el('table', 'runs wp-orders');
    const head = el('tr');
    head.append(el('th', '', 'Method'), el('th', 'num', 'Order (slope vs h)'));
    for (const h of steps) head.append(el('th', 'num', `h = ${short(h)}`));
    const thead = el('thead');
    thead.append(head);
    const tbody = el('tbody');
    cs.forEach((c, i) => {
      const tr = el('tr', 'wp-method');
      tr.dataset.method = c.label;
      const name = el('th');
      const swatch = el('span', 'swatch');
      swatch.style.background = runColor(i);
      name.append(swatch, c.label);
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
      for (const r of c.failed) failures.append(el('li', '', `${c.label} at h = ${short(r.step)} failed: ${r.error ?? 'no message'}`));
    }
    const wrap = el('div');
    wrap.append(table);
    if (failures.children.length) wrap.append(failures);
    return wrap;
  }

  #width() {
    const w = this.plots.clientWidth || 900;
    return Math.max(320, Math.floor(w >= 900 ? w / 2 - 40 : w - 34));
  }

  #resize() {
    const width = this.#width();
    for (const c of this.charts) c.u.setSize({ width, height: HEIGHT });
  }

  #status(state, text) {
    this.status.dataset.state = state;
    this.status.textContent = text;
  }
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
  return parts.length ? `${c.label} (${parts.join(', ')})` : c.label;
}

// 0.000123 → "1.2e-4"; 0.5 → "0.5": axis ticks and table heads stay short.
function short(v) {
  if (v === null || v === undefined) return '';
  const a = Math.abs(v);
  return a !== 0 && (a < 1e-3 || a >= 1e4) ? v.toExponential(1).replace('e-', 'e−') : String(Number(v.toPrecision(3)));
}
