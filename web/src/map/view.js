// The Map view: the Explore form's scene and methods swept over one or two axes by
// `POST /sweep`, streamed, drawn as a heat map of the chosen method's verdict on the chosen
// integral (or of log₁₀ of its largest error) that fills in as cells arrive, in any order;
// with one axis, a line plot of every method's largest error beside it. Hovering a cell
// names it and gives its numbers; clicking it opens that run in Explore. A sweep saved as
// JSON or CSV opens from a file (either download, `POST /sweep`'s answer, or a sweep the
// Python package published, whose methods written in Python run nowhere else: their cells
// do not open). Presets
// (presets.json) set the scene and the axes and compute at once. Its state is the form's
// plus the map's settings, in the URL as `?view=map&…` (sweep.js); `run=1` computes on load.

import { ApiError, retrying, sweep } from '../data/api.js';
import { findMethod, tableauChoice, takesTableau } from '../data/catalog.js';
import { sceneCaption, slug, systemSlug } from '../data/custom.js';
import { Heatmap, KIND_MARKS, OTHER_KINDS } from './heatmap.js';
import { MapControls } from './controls.js';
import { MapLine } from './line.js';
import PRESETS from './presets.json';
import { axisPaths, cellAtXY, cellXY, decodeSettings, mapPresets, mapQuery, presetSetup, sweepBody } from './sweep.js';
import { SweepResult, cellLines, cellState, fmt, sweepFromCSV, sweepFromJSON, writtenInPython } from './sweepresult.js';
import { VERDICTS } from '../data/verdicts.js';
import { download, el } from '../draw/dom.js';
import { fileButtons } from '../draw/export.js';
import { fieldLabel, humanLabel, sweptLabel } from '../data/labels.js';
import { heatmapCanvas, heatmapSvg } from './heatexport.js';

export class MapView {
  /**
   * `read()`: the form's `{state, invalid}`; `fill(state)`: shows a state in the form;
   * `onOpen(body)`: runs a `/simulate` body in Explore; `onFormError(path, message)`: marks
   * a field of the form (true when it has one); `onEdit()`: shows Explore.
   */
  constructor(root, { read, fill, catalog, onOpen, onFormError, onEdit }) {
    Object.assign(this, { root, read, fill, catalog, onOpen, onFormError });
    this.controller = null;
    this.result = null;
    this.computedFor = null;
    this.frame = 0;
    this.status = root.querySelector('.view-status');
    this.progressBar = root.querySelector('.map-progress');
    this.progressText = root.querySelector('.map-progress-text');
    this.errorBox = root.querySelector('.map-error');
    this.scene = root.querySelector('.map-scene-text');
    this.legend = root.querySelector('.map-legend');
    this.criterion = root.querySelector('.map-criterion');
    this.card = root.querySelector('.map-card');
    this.controls = new MapControls(root.querySelector('.map-controls'), { onChange: () => this.#changed() });
    this.heatmap = new Heatmap(root.querySelector('.map-plot'), { onOpen: (cell) => this.#open(cell), format: fmt });
    this.line = new MapLine(root.querySelector('.map-line'), catalog, () => this.#picture('line'));
    root.querySelector('.map-card .plot-head').append(
      fileButtons(() => this.#picture('map'), { png: (d) => heatmapCanvas(this.heatmap, d), svg: (d) => heatmapSvg(this.heatmap, d) }),
    );
    const { settings, warnings } = decodeSettings(location.search);
    this.controls.fill(settings);
    // `run=1` of an Explore link is Explore's: only a map link computes the map on load.
    this.autoRun = settings.run && new URLSearchParams(location.search).get('view') === 'map';
    if (warnings.length) this.#banner(warnings.join('; '));
    root.querySelector('.map-controls').addEventListener('submit', (e) => {
      e.preventDefault();
      this.load();
    });
    root.querySelector('.map-cancel').addEventListener('click', () => this.controller?.abort());
    root.querySelector('.map-edit').addEventListener('click', () => onEdit());
    root.querySelector('.map-json').addEventListener('click', () => {
      if (this.result) download(`${this.computed.stem}.json`, 'application/json', JSON.stringify(this.result.toJSON(), null, 1));
    });
    root.querySelector('.map-csv').addEventListener('click', () => {
      if (this.result) download(`${this.computed.stem}.csv`, 'text/csv', this.result.toCSV());
    });
    root.querySelector('.map-open').addEventListener('change', (e) => this.#openFile(e.target));
    this.#presetButtons();
  }

  /** Shows the form's scene and the settings; computes when the link said `run=1`. */
  show() {
    this.#sync();
    if (this.autoRun && !this.controller) {
      this.autoRun = false;
      this.load();
    }
  }

  /** Takes the settings of a link (back/forward). */
  restore(query) {
    const { settings } = decodeSettings(query);
    this.controls.fill(settings);
    this.autoRun = settings.run && computeKey(this.read().state, this.catalog, settings) !== this.computedFor;
  }

  async load() {
    this.errorBox.hidden = true;
    this.controls.clearErrors();
    const { state, invalid } = this.read();
    if (invalid.length) {
      this.#status('error', `The Explore form has errors (${invalid.map((e) => e.path).join(', ')}): fix them there.`);
      return;
    }
    if (this.controls.check()) {
      this.#status('error', 'Fix the marked axis, then compute again.');
      return;
    }
    const settings = this.controls.read();
    this.pending = computeKey(state, this.catalog, settings);
    history.replaceState(null, '', `?${mapQuery(state, this.catalog, settings, true)}`);
    this.controller?.abort();
    const mine = new AbortController();
    this.controller = mine;
    this.logX = settings.axes.length === 1 && settings.axes[0].kind === 'logspace';
    this.#busy(true);
    this.#progress(0);
    this.#status('running', 'Starting…');
    let done = null;
    let shutdown = null;
    try {
      await retrying(
        () =>
          sweep(sweepBody(state, settings, this.catalog), {
            signal: mine.signal,
            onEvent: (name, data) => {
              if (this.controller !== mine) return;
              if (name === 'start') {
                this.result = new SweepResult(data);
                // The scene as computed, for the files: the form may change afterwards.
                this.computed = { caption: this.scene.textContent, stem: this.#stem() };
                this.computedFor = this.pending;
                this.#offer();
              } else if (name === 'cell') this.result?.addCell(data);
              else if (name === 'progress') this.result?.progress(data);
              else if (name === 'done') {
                done = data;
                this.result?.finish(data);
              } else if (name === 'shutdown') shutdown = data;
              if (this.result && !done) this.#status('running', `Computing: ${this.result.received} of ${this.result.cells} cells…`);
              this.#schedule();
            },
          }),
        (wait) => this.#status('running', `The server is busy (every simulation slot is taken); retrying in ${wait} s…`),
        mine.signal,
      );
      if (this.controller !== mine) return;
      if (done) {
        const r = this.result;
        const extra = [done.failed ? `${done.failed} failed` : '', done.invalid ? `${done.invalid} invalid` : ''].filter(Boolean).join(', ');
        this.#status('done', `Done: ${r.cells} cells, ${done.rows} runs in ${seconds(done.elapsed_ms)}${extra ? ` (${extra})` : ''}. Hover a cell for its numbers; click it to open its plots in Explore.`);
      } else if (shutdown) {
        this.#status('error', 'The server shut down during the sweep; the map shows what arrived.');
        this.#banner(shutdown.error ?? 'The server is shutting down.');
      } else {
        this.#status('error', 'The stream ended before the sweep was done (the server stopped or the connection broke); the map shows what arrived.');
      }
    } catch (e) {
      if (this.controller !== mine) return;
      if (e.name === 'AbortError') {
        const r = this.result;
        this.#status('cancelled', r ? `Cancelled after ${r.received} of ${r.cells} cells; the map shows what arrived.` : 'Cancelled.');
      } else if (e instanceof ApiError) this.#rejected(e);
      else this.#status('error', `The connection failed: ${e.message}.`);
    } finally {
      if (this.controller === mine) {
        this.controller = null;
        this.#busy(false);
        this.#render();
      }
    }
  }

  // A 4xx: at the axis field it names, else at the Explore form's field, else in the banner.
  #rejected(e) {
    const where = e.path ? ` (field ${e.path})` : '';
    if (this.controls.showError(e.path, e.message)) {
      this.#status('error', `The server rejected an axis: ${e.message}${where}`);
    } else if (e.path && this.onFormError(e.path, e.message)) {
      this.#status('error', `The server rejected a field of the Explore form: ${e.message}${where}. Fix it in Explore.`);
    } else {
      this.#status('error', `The server rejected the sweep: ${e.message}${where}`);
    }
  }

  #changed() {
    this.#sync();
    this.#render();
  }

  // The scene line, path suggestions, method and integral choices, and the URL.
  #sync() {
    const { state } = this.read();
    this.scene.textContent = `${sceneCaption(state, this.catalog)} · ${state.methods.length} method${state.methods.length === 1 ? '' : 's'}`;
    this.controls.suggest(axisPaths(state, this.catalog));
    this.#offer();
    const settings = this.controls.read();
    const key = computeKey(state, this.catalog, settings);
    // The link computes on load only while it describes the map shown (or being computed).
    const shown = (this.controller && key === this.pending) || (this.result && key === this.computedFor);
    history.replaceState(null, '', `?${mapQuery(state, this.catalog, settings, Boolean(shown))}`);
    this.#render();
  }

  // The methods and integrals to choose from: the sweep's, else the form's.
  #offer() {
    if (this.result) {
      this.controls.offer(this.result.methods.map((m) => m.label ?? m.id), this.result.integrals);
      return;
    }
    const { state } = this.read();
    this.controls.offer(state.methods.map((m) => methodLabel(this.catalog, m)), state.integrals);
  }

  #schedule() {
    if (!this.frame) this.frame = requestAnimationFrame(() => this.#render());
  }

  #render() {
    cancelAnimationFrame(this.frame);
    this.frame = 0;
    const r = this.result;
    this.card.hidden = !r;
    if (!r) return;
    this.#progress(r.fraction);
    const { method, integral, color } = this.controls.read();
    const axes = r.axes;
    const last = axes[axes.length - 1];
    const paths = axes.map((a) => a.path);
    const label = sweptLabel(r.methods[method]?.label ?? `method ${method}`, paths, Number(method));
    this.heatmap.set({
      xs: last.values,
      ys: axes.length > 1 ? axes[0].values : null,
      xTitle: fieldLabel(last.path),
      yTitle: fieldLabel(axes[0].path),
      cells: r.cells,
      mode: color,
      label: `${color === 'log' ? 'log₁₀ of the largest error' : 'verdict'} of ${label} on ${integral} over ${axes.map((a) => fieldLabel(a.path)).join(' × ')}`,
      stateOf: (c) => cellState(r.row(c, method), integral),
      linesOf: (c) => cellLines(r, c, method, integral),
      xyOf: (c) => cellXY(c, r.counts),
      cellAt: (x, y) => cellAtXY(x, y, r.counts),
    });
    this.root.querySelector('.map-title').textContent = `${label} · ${integral} · ${color === 'log' ? 'log₁₀ of the largest error' : 'verdict'}`;
    if (axes.length === 1) this.line.update(r, integral, this.logX, method);
    else this.line.destroy();
    this.#legend(color, r);
  }

  #legend(color, r) {
    const item = (kind, mark, text) => {
      const i = el('span', 'legend-item');
      i.append(el('span', `map-swatch ${kind}`, mark), ` ${text}`);
      return i;
    };
    const kinds = color === 'log'
      ? [el('span', 'legend-item', 'Colour: log₁₀ of the largest error of the integral over the run (bar at the right; errors below 10⁻¹⁶ at the bottom).')]
      : VERDICTS.map((v) => item(v.kind, v.letter, `${v.label}: ${v.text}`));
    this.legend.replaceChildren(
      ...kinds,
      ...OTHER_KINDS.map((k) => item(k.kind, KIND_MARKS[k.kind], k.long)),
      item('pending', '', 'not computed yet'),
    );
    this.criterion.textContent = r.criterion ? `Criterion: ${r.criterion}` : '';
  }

  #open(cell) {
    const row = this.result?.row(cell, this.controls.read().method);
    if (writtenInPython(row)) {
      this.#status('done', `${row.method.label ?? row.method.name} is written in Python: it runs only in the nhlab Python package, so its run cannot be opened here.`);
      return;
    }
    if (row?.simulate) this.onOpen(row.simulate);
  }

  // A sweep saved as JSON or CSV (by its name or type), shown as if computed here: its own
  // axes, methods and integrals.
  async #openFile(input) {
    const file = input.files?.[0];
    if (!file) return;
    this.controller?.abort();
    this.errorBox.hidden = true;
    let result;
    try {
      const text = await file.text();
      result = isCSV(file) ? sweepFromCSV(text) : sweepFromJSON(JSON.parse(text));
    } catch (e) {
      this.#status('error', `Cannot open ${file.name}: ${e.message}.`);
      return;
    } finally {
      input.value = '';
    }
    this.result = result;
    this.computedFor = null;
    this.computed = { caption: `${file.name} (opened from a file)`, stem: file.name.replace(/\.(json|csv)$/i, '') };
    const xs = result.axes.length === 1 ? result.axes[0].values : [];
    this.logX = xs.length > 2 && xs.every((x) => x > 0) && Math.abs(Math.log(xs[2] / xs[1]) - Math.log(xs[1] / xs[0])) < 1e-9;
    this.#busy(false);
    // The link no longer computes on load: it names the form's scene, not the file.
    this.#sync();
    const runs = result.rows();
    const python = runs.some(writtenInPython) ? ' Methods written in Python ran in the Python package: their cells show their numbers but do not open in Explore.' : '';
    this.#status('done', `Opened ${file.name}: ${result.cells} cells, ${runs.length} runs. Hover a cell for its numbers; click it to open its plots in Explore.${python}`);
  }

  #presetButtons() {
    const buttons = mapPresets(PRESETS, this.catalog).map((p) => {
      const b = el('button', 'experiment', p.label);
      b.type = 'button';
      b.dataset.preset = p.id;
      b.title = p.hint ?? '';
      b.addEventListener('click', () => {
        const { state, settings } = presetSetup(p, this.catalog);
        this.result = null;
        this.fill(state);
        this.controls.fill(settings);
        this.#sync();
        this.load();
      });
      return b;
    });
    this.root.querySelector('.map-presets').replaceChildren(...buttons);
  }

  // What an exported picture says of itself: its title, the scene, how to read it, its file.
  #picture(kind) {
    const { integral, color } = this.controls.read();
    const line = kind === 'line';
    const title = line ? `Largest ${integral} error against ${fieldLabel(this.result?.axes[0]?.path)}` : this.root.querySelector('.map-title').textContent;
    const stem = `${this.computed.stem}${line ? '-line' : ''}`;
    // The line plot's export draws its own legend; only the heat map's needs a key.
    if (line) return { title, caption: this.computed.caption, stem };
    const others = OTHER_KINDS.map((k) => `${KIND_MARKS[k.kind]} ${k.short}`);
    const key = color === 'log'
      ? `Colour: log₁₀ of the largest error over the run (the bar at the right); ${others.join(', ')}`
      : [...VERDICTS.map((v) => `${v.letter} ${v.label}`), ...others].join(' · ');
    const pending = this.result.received < this.result.cells ? ` · pale: not computed (${this.result.received} of ${this.result.cells} cells)` : '';
    return { title, caption: this.computed.caption, key: `${key}${pending}`, stem };
  }

  #stem() {
    const { state } = this.read();
    const axes = this.result.axes.map((a) => slug(a.path)).join('-x-');
    return ['nhlab-map', systemSlug(state.system, this.catalog), axes].filter(Boolean).join('-');
  }

  #busy(busy) {
    this.root.querySelector('.map-run').disabled = busy;
    this.root.querySelector('.map-cancel').disabled = !busy;
    for (const b of this.root.querySelectorAll('.map-json, .map-csv')) b.disabled = !this.result;
  }

  #progress(fraction) {
    this.progressBar.value = fraction;
    this.progressText.textContent = `${Math.floor(fraction * 100)}%`;
  }

  #status(state, text) {
    this.status.dataset.state = state;
    this.status.textContent = text;
  }

  #banner(text) {
    this.errorBox.textContent = text;
    this.errorBox.hidden = false;
  }
}

// What a sweep computes (the scene, methods and axes; not what the map shows of it).
function computeKey(state, catalog, settings) {
  return mapQuery(state, catalog, { ...settings, method: 0, integral: '', color: 'verdict' });
}

// A method of the form as the choice names it before the server labels it: the catalog's
// label of a default method with the same parameters, a PRK method's its tableau's label with
// its constraint (`PRK[gauss3]`), else its name and parameters.
function methodLabel(catalog, m) {
  const info = findMethod(catalog, m.id);
  const byTableau = takesTableau(catalog, m.id) ? tableauChoice(catalog, m.tableau, m.constraint).entry?.label : undefined;
  if (byTableau) return `${byTableau}${m.composition ? `∘${m.composition}` : ''}`;
  const same = (d) => d.id === m.id && !m.composition && (info?.params ?? []).every((p) => (d[p.name] ?? p.default) === (m.params?.[p.name] ?? p.default));
  const listed = (catalog.default_methods ?? []).find(same);
  if (listed?.label) return listed.label;
  const params = Object.entries(m.params ?? {}).map(([k, v]) => `${k} = ${v}`);
  const name = `${info?.name ?? m.id}${m.composition ? ` ∘${m.composition}` : ''}`;
  return params.length ? `${name} (${params.join(', ')})` : name;
}

function isCSV(file) {
  return /\.csv$/i.test(file.name) || file.type === 'text/csv';
}

function seconds(ms) {
  return Number.isFinite(ms) ? (ms < 1000 ? `${Math.round(ms)} ms` : `${(ms / 1000).toFixed(1)} s`) : '–';
}
