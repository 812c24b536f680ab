// The card the Trajectory and Section panels share: a title, the panel's controls, the scene
// it shows, the x–y plot (xyplot.js), a note, a legend of each run's line and marker (its
// method's look, as in every plot; a failed run says so), PNG/SVG/CSV exports and a text
// summary for screen readers. The panel says what to draw; the card draws it.

import { el, download } from './dom.js';
import { fileButtons } from './export.js';
import { swatch } from './markers.js';
import { methodStyle } from './palette.js';
import { humanLabel } from '../data/labels.js';
import { XYPlot } from './xyplot.js';
import { xyCanvas, xySvg } from './xyexport.js';

export class XYCard {
  /** `panel`: the card's data-panel name; `title`; `sub`: the line beside the title. */
  constructor(container, { panel, title, sub }) {
    this.card = el('section', 'dyn-card');
    this.card.dataset.panel = panel;
    const head = el('header', 'plot-head');
    this.sub = el('span', 'plot-sub', sub);
    head.append(el('h3', '', title), this.sub);
    this.controls = el('div', 'dyn-controls');
    this.scene = el('p', 'plot-scene');
    const target = el('div', 'dyn-plot');
    this.note = el('p', 'dyn-note');
    this.note.hidden = true;
    this.legend = el('div', 'legend dyn-legend');
    const foot = el('div', 'plot-foot');
    this.alt = el('p', 'sr-only plot-alt');
    this.card.append(head, this.controls, this.scene, target, this.note, this.legend, foot, this.alt);
    container.append(this.card);
    this.plot = new XYPlot(target, container);
    this.spec = null;
    this.describe = () => ({ title, caption: '', stem: 'nhlab' });
    const csv = el('button', 'secondary small export-csv', 'CSV');
    csv.type = 'button';
    csv.title = 'Download the plotted values as CSV';
    csv.addEventListener('click', () => {
      const d = this.describe();
      if (d.csv) download(`${d.stem}.csv`, 'text/csv', d.csv());
    });
    const buttons = fileButtons(() => this.describe(), {
      png: (d) => xyCanvas(this.spec, d, this.plot.width()),
      svg: (d) => xySvg(this.spec, d, this.plot.width()),
    });
    buttons.append(csv);
    foot.append(buttons);
    this.card.xy = this; // for the browser test: what is drawn
    this.clear();
  }

  /**
   * Draws `runs` (a Result's) with `catalog`'s looks: `columns(run)` gives a run's
   * `{xs, ys}` or null; `mode`, `xLabel`, `yLabel`; `describe()` the exports' `{title,
   * caption, stem, csv}`; `empty`: the note when no run has columns.
   */
  draw(runs, catalog, { columns, mode, xLabel, yLabel, describe, empty }) {
    this.describe = describe;
    const series = [];
    runs.forEach((run, i) => {
      const xy = columns(run);
      if (!xy) return;
      const label = run.status === 'failed' ? `${humanLabel(run.label)} (failed)` : humanLabel(run.label);
      const instrument = catalog?.methods?.find((m) => m.id === run.method?.id)?.instrument === true;
      series.push({ ...xy, label, run: i, status: run.status, instrument, style: methodStyle(catalog, run.method), width: Math.max(1, 2 - 0.2 * i) });
    });
    // The reference beneath the methods: drawn first.
    series.sort((a, b) => Number(b.instrument) - Number(a.instrument));
    this.spec = { series, mode, xLabel, yLabel };
    this.plot.draw(this.spec);
    this.#legend(series);
    const d = describe();
    this.scene.textContent = d.caption;
    this.scene.hidden = !d.caption;
    const what = series.map((s) => `${s.label}: ${s.xs.length} ${mode === 'points' ? 'crossings' : 'samples'}`);
    const text = `${d.title} (${d.caption}): ${what.length ? what.join('; ') : 'nothing drawn'}.`;
    if (this.alt.textContent !== text) {
      this.alt.textContent = text;
      this.plot.canvas.setAttribute('aria-label', text);
    }
    const missing = runs.length > 0 && series.length === 0;
    this.setNote(missing ? empty : '');
  }

  /** What is drawn, per series: label, points, colour, marker (the browser test reads it). */
  get drawn() {
    return (this.spec?.series ?? []).map((s) => ({ label: s.label, points: s.xs.length, colour: s.style.colour, marker: s.style.marker }));
  }

  setNote(text) {
    this.note.textContent = text;
    this.note.hidden = !text;
  }

  #legend(series) {
    const key = series.map((s) => `${s.label}|${s.style.colour}|${s.style.marker}`).join(',');
    if (this.legend.dataset.key === key) return;
    this.legend.dataset.key = key;
    this.legend.replaceChildren(
      ...series.map((s) => {
        const item = el('span', 'legend-item');
        item.dataset.run = s.run;
        item.append(swatch(s.style), el('span', 'legend-label', s.label));
        return item;
      }),
    );
  }

  clear() {
    this.spec = { series: [], mode: 'lines', xLabel: '', yLabel: '' };
    this.plot.draw(this.spec);
    this.legend.replaceChildren();
    this.legend.dataset.key = '';
  }
}
