// The Work–precision view: posts the form's scene and methods to `/work-precision` (the
// scene's step and halvings of it, or a list of steps) and draws two log–log plots
// (plots.js), one line per method, with each method's fitted order. Its settings are
// checked at their fields before anything is sent; while it runs, the elapsed time shows
// and Cancel aborts the request (the server stops when the client leaves); after an error
// or a cancel, the plots of the previous request stay, dimmed and marked stale. Its state is
// the form's plus the settings, in the URL as `?view=work-precision&…`.

import { ApiError, fetchWorkPrecision, retrying } from '../data/api.js';
import { sceneCaption, sceneStem } from '../data/custom.js';
import { ORIENTS, decodeSettings, readSettings, workPrecisionBody, workPrecisionQuery } from './precision.js';
import { HEIGHT, renderAnswer } from './plots.js';
import { fieldLabel } from '../data/labels.js';
import { clock } from '../data/timing.js';
import { el } from '../draw/dom.js';
import { encodeState } from '../data/state.js';

const FIELDS = ['levels', 'steps', 'repeats'];

export class WorkPrecisionView {
  /** `read()`: the form's `{state, invalid}`; `catalog`: `GET /systems`; `onFormError(path,
   *  message)`: marks an Explore field the server rejected. */
  constructor(root, { read, catalog, onFormError }) {
    this.root = root;
    this.read = read;
    this.catalog = catalog;
    this.onFormError = onFormError ?? (() => false);
    this.controller = null;
    this.charts = [];
    this.answer = null;
    // The scene and settings last sent (the orientation aside: it only redraws), so that
    // coming back to the tab recomputes only for a changed request, and a request that was
    // cancelled or failed is not sent again until Run is pressed.
    this.sentFor = null;
    const q = (c) => root.querySelector(c);
    this.status = q('.view-status');
    this.plots = q('.wp-plots');
    this.table = q('.wp-table');
    this.stale = q('.wp-stale');
    this.progress = q('.wp-progress-line');
    this.inputs = { levels: q('.wp-levels'), steps: q('.wp-steps'), repeats: q('.wp-repeats') };
    this.orient = q('.wp-orient');
    this.cancel = q('.wp-cancel');
    const settings = decodeSettings(location.search);
    for (const f of FIELDS) this.inputs[f].value = settings[f];
    this.orient.value = settings.orient;
    q('.wp-run').addEventListener('click', () => this.load());
    this.cancel.addEventListener('click', () => this.controller?.abort());
    this.orient.addEventListener('change', () => {
      this.#url();
      if (this.answer) this.#render(this.answer);
    });
    for (const f of FIELDS) this.inputs[f].addEventListener('change', () => this.#url());
    new ResizeObserver(() => this.#resize()).observe(this.plots);
  }

  /** Computes for the form's current scene, unless it is the one last sent. */
  show() {
    this.#url();
    if (this.#request() !== this.sentFor && !this.controller) this.load();
  }

  // The request the view would send now, as a string: the scene and the settings as typed.
  #request() {
    const { state } = this.read();
    return JSON.stringify([encodeState({ ...state, run: false }, this.catalog), FIELDS.map((f) => this.inputs[f].value)]);
  }

  // The settings as typed, checked against the final time (the form's, else the preset's).
  #settings(state) {
    const raw = Object.fromEntries(FIELDS.map((f) => [f, this.inputs[f].value]));
    const tEnd = state.t_end ?? this.catalog.systems.find((s) => s.id === state.system)?.presets?.find((p) => p.id === state.preset)?.t_end;
    return readSettings(raw, tEnd);
  }

  // Writes the view's URL (a setting that does not pass as typed, so a reload shows it
  // again).
  #url() {
    const { state } = this.read();
    const { settings, errors } = this.#settings(state);
    const shown = { ...settings, orient: this.orient.value };
    for (const { field } of errors) shown[field] = field === 'steps' ? [this.inputs.steps.value] : this.inputs[field].value;
    history.replaceState(null, '', `?${workPrecisionQuery(state, this.catalog, shown)}`);
  }

  async load() {
    this.#clearErrors();
    this.sentFor = this.#request();
    // A new Run replaces the request in flight, whether or not the new one can be sent.
    this.#stop();
    const { state, invalid } = this.read();
    if (invalid.length) {
      const names = invalid.map((e) => `${fieldLabel(e.path) ?? e.path}: ${e.message}`).join('; ');
      this.#fail(`The Explore form has errors (${names}): fix them there.`);
      this.#markStale('Stale: from the previous request (the new one has errors).');
      return;
    }
    const { settings, errors } = this.#settings(state);
    if (errors.length) {
      for (const e of errors) this.#fieldError(e.field, e.message);
      this.#fail(`Not sent: ${errors.map((e) => `${fieldLabel(e.field)}: ${e.message}`).join('; ')}.`);
      this.#markStale('Stale: from the previous request (the new one has errors).');
      return;
    }
    this.#url();
    const mine = new AbortController();
    this.controller = mine;
    this.#busy(true);
    this.#markStale(this.answer ? 'Stale: from the previous request, while the new one runs.' : '');
    const started = performance.now();
    const what = settings.steps ? `${settings.steps.length} step sizes` : `${settings.levels} step sizes${state.step ? ` from h = ${state.step}` : ''}`;
    let note = `Measuring ${state.methods.length} methods at ${what}, ${settings.repeats} repeats each`;
    const tick = () => {
      if (this.controller === mine) this.#status('running', `${note}… ${clock(performance.now() - started)} elapsed.`);
    };
    tick();
    const timer = setInterval(tick, 500);
    try {
      const answer = await retrying(
        () => fetchWorkPrecision(workPrecisionBody(state, settings, this.catalog), { signal: mine.signal }),
        (wait) => {
          note = `The server is busy; retrying in ${wait} s`;
          tick();
        },
        mine.signal,
      );
      if (this.controller !== mine) return;
      this.#render(answer);
      this.#markStale('');
      const failed = answer.rows.filter((r) => r.status !== 'ok').length;
      const ref = answer.reference;
      // A system whose exact solution is known is measured against it.
      const refText = ref.exact ? 'reference: the exact solution' : `reference: Dop853, ${ref.steps} steps${ref.cached ? ', cached' : `, ${ref.elapsed_ms.toFixed(1)} ms`}`;
      const scene = answer.scene ? ` on ${sceneCaption(answer.scene, this.catalog)}` : '';
      const took = clock(performance.now() - started);
      this.#status(failed ? 'done-failed' : 'done', `Done in ${took}: ${answer.rows.length} runs${scene}${failed ? `, ${failed} failed (see the table)` : ''}; ${refText}.`);
    } catch (e) {
      if (this.controller !== mine) return;
      const previous = this.answer ? 'Stale: from the previous request' : '';
      if (e.name === 'AbortError') {
        this.#status('cancelled', `Cancelled after ${clock(performance.now() - started)}; the server stopped.`);
        this.#markStale(previous && `${previous} (this one was cancelled).`);
        return;
      }
      this.#markStale(previous && `${previous} (this one failed).`);
      this.#fail(this.#message(e));
    } finally {
      clearInterval(timer);
      if (this.controller === mine) {
        this.controller = null;
        this.#busy(false);
      }
    }
  }

  // An error in the page's words: the label of the field it names, marked there.
  #message(e) {
    if (!(e instanceof ApiError) || !e.path) return `Work–precision failed: ${e.message}`;
    const head = e.path.split(/[.[]/)[0];
    const label = fieldLabel(e.path);
    if (FIELDS.includes(head)) {
      this.#fieldError(head, e.message);
      return `Work–precision failed at ${label}: ${e.message}`;
    }
    const marked = this.onFormError(e.path, e.message);
    return `Work–precision failed at ${label}${marked ? ' (marked in the Explore form)' : ', in the Explore form'}: ${e.message}`;
  }

  #render(answer) {
    this.answer = answer;
    for (const c of this.charts) c.u.destroy();
    const scene = answer.scene ? sceneCaption(answer.scene, this.catalog) : '';
    this.charts = renderAnswer(answer, {
      plots: this.plots,
      table: this.table,
      orient: ORIENTS.includes(this.orient.value) ? this.orient.value : ORIENTS[0],
      scene,
      stem: sceneStem(answer.scene, this.catalog),
      width: this.#width(),
      catalog: this.catalog,
    });
  }

  #fieldError(field, message) {
    const input = this.inputs[field];
    const box = input.closest('.wp-field');
    box.classList.add('invalid');
    input.setAttribute('aria-invalid', 'true');
    const p = el('p', 'field-error', `${fieldLabel(field)}: ${message}`);
    p.setAttribute('role', 'alert');
    box.append(p);
  }

  #clearErrors() {
    for (const p of this.root.querySelectorAll('.wp-field .field-error')) p.remove();
    for (const f of FIELDS) {
      this.inputs[f].closest('.wp-field').classList.remove('invalid');
      this.inputs[f].removeAttribute('aria-invalid');
    }
  }

  // Dims the plots and table with a note, or (empty text) shows them as current.
  #markStale(text) {
    const stale = Boolean(text) && Boolean(this.answer);
    this.stale.hidden = !stale;
    this.stale.textContent = stale ? text : '';
    this.plots.classList.toggle('stale', stale);
    this.table.classList.toggle('stale', stale);
  }

  // Abandons the request in flight (the server stops when the client leaves).
  #stop() {
    const running = this.controller;
    this.controller = null;
    running?.abort();
    this.#busy(false);
  }

  #busy(busy) {
    this.cancel.disabled = !busy;
    this.progress.hidden = !busy;
  }

  #fail(text) {
    this.#status('error', text);
  }

  #width() {
    const w = this.plots.clientWidth || 900;
    return Math.max(220, Math.floor(w >= 900 ? w / 2 - 40 : w - 34));
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
