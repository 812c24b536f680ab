// The Map view's line plot for a single axis: the largest error of the chosen integral
// against the axis value, one line per method (log scale; the x axis too when the values are
// all positive and log-spaced), filling in as cells arrive. Failed, invalid and pending cells
// are gaps, never points; errors below the floor sit on it.

import uPlot from 'uplot';
import { LOG_FLOOR } from './heatmap.js';
import { powerOfTen } from '../draw/axes.js';
import { runWidth } from '../draw/plots.js';
import { methodStyle } from '../draw/palette.js';
import { legendSwatches, seriesStyle } from '../draw/markers.js';
import { fmt } from './sweepresult.js';
import { fieldLabel, humanLabel } from '../data/labels.js';
import { exportButtons, withTicks } from '../draw/export.js';

const HEIGHT = 300;

export class MapLine {
  /** `catalog`: GET /systems, for each method's colour and marker (palette.js);
   *  `describe()`: the exported files' `{title, caption, stem}` (no PNG/SVG buttons without). */
  constructor(container, catalog = null, describe = null) {
    this.container = container;
    this.catalog = catalog;
    this.describe = describe;
    this.u = null;
    this.key = '';
    new ResizeObserver(() => this.u?.setSize({ width: this.#width(), height: HEIGHT })).observe(container);
  }

  /**
   * Draws `result` (a SweepResult with one axis) for `integral`; `logX` puts x on a log scale;
   * `chosen` is the method the heat map shows (drawn widest).
   */
  update(result, integral, logX, chosen) {
    const values = result.axes[0].values;
    const order = values.map((v, i) => [v, i]).sort((a, b) => a[0] - b[0]);
    const xs = order.map(([v]) => v);
    const lines = result.methods.map((_, m) =>
      order.map(([, cell]) => {
        const row = result.row(cell, m);
        const max = row?.status === 'ok' ? row.verdicts?.[integral]?.max : null;
        return typeof max === 'number' && Number.isFinite(max) ? Math.max(max, LOG_FLOOR) : null;
      }),
    );
    const key = [result.axes[0].path, integral, logX, chosen, result.methods.map((m) => m.label).join('|')].join('/');
    if (!this.u || key !== this.key) this.#build(result, integral, logX, chosen, key);
    this.u.setData([xs, ...lines]);
  }

  destroy() {
    this.u?.destroy();
    this.u = null;
    this.key = '';
    this.container.replaceChildren();
  }

  #build(result, integral, logX, chosen, key) {
    this.destroy();
    this.key = key;
    const axis = (label, values) => ({ label, stroke: '#475569', grid: { stroke: '#e2e8f0' }, ticks: { stroke: '#cbd5e1' }, values });
    const xValues = (u, splits) => splits.map((v) => (v === null || v === undefined ? '' : fmt(v)));
    const styles = result.methods.map((m) => methodStyle(this.catalog, m));
    const opts = {
      width: this.#width(),
      height: HEIGHT,
      scales: { x: logX ? { time: false, distr: 3, log: 10 } : { time: false }, y: { distr: 3, log: 10 } },
      plugins: [withTicks()],
      axes: [axis(fieldLabel(result.axes[0].path), xValues), { ...axis(`largest ${integral} error over the run`, decades), size: 70 }],
      series: [
        { label: fieldLabel(result.axes[0].path), value: (u, v) => (v === null ? '' : fmt(v)) },
        ...result.methods.map((m, i) => ({
          ...seriesStyle(styles[i], { width: i === chosen ? 3 : runWidth(i + 1), size: i === chosen ? 8 : 6, sparse: false }),
          label: humanLabel(m.label ?? m.id),
          spanGaps: false,
          value: (u, v) => (v === null ? '–' : v.toExponential(2)),
        })),
      ],
    };
    const card = document.createElement('div');
    card.className = 'map-line-plot';
    this.container.replaceChildren(card);
    this.u = new uPlot(opts, [[], ...result.methods.map(() => [])], card);
    legendSwatches(this.u, styles);
    card.uplot = this.u; // for the browser test: the drawn series
    if (this.describe) card.append(exportButtons(() => this.u, () => ({ ...this.describe(), styles })));
  }

  #width() {
    return Math.max(320, (this.container.clientWidth || 800) - 8);
  }
}

// Log-axis labels: whole decades only, every k-th when they would crowd (16 px apart at least).
function decades(u, splits) {
  const exponent = (v) => (v > 0 ? Math.log10(v) : NaN);
  const whole = (v) => Math.abs(exponent(v) - Math.round(exponent(v))) < 1e-9;
  const count = splits.filter((v) => v && whole(v)).length;
  const stride = Math.max(1, Math.ceil((count * 16) / Math.max(1, u.bbox.height / (window.devicePixelRatio || 1))));
  return splits.map((v) => (v && whole(v) && Math.round(exponent(v)) % stride === 0 ? powerOfTen(Math.round(exponent(v))) : ''));
}
