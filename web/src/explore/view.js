// The Explore view: the form (a scene and its methods), Run, and the stream of /simulate drawn
// as it arrives. Submitting the form (or a URL with run=1) runs a simulation, feeds the
// stream into a Result and redraws the plots, progress and runs table once per animation
// frame; Cancel aborts the fetch. "Custom system" in the system select opens the formula
// editor, filled from the system shown or from the built-in its "Start from" select picks, in
// the paper's form or the general one (the form's moves between states are in
// transitions.js). The results say whether the scene's system is in the paper's class. Under
// the error plots, the Trajectory and Section panels draw each run's observables and its
// Poincaré section, which the run asks for with the panels' picks. The view's state is the
// form's and lives in the URL (state.js); the other views read and fill the same form.

import { ApiError, retrying, simulate } from '../data/api.js';
import { paperClassLine, paperExperiments } from '../data/catalog.js';
import { CUSTOM, sceneCaption, sceneStem } from '../data/custom.js';
import { dynamicsSystem } from '../data/dynamics.js';
import { fieldLabel } from '../data/labels.js';
import { Result } from '../data/result.js';
import { decodeState, encodeState, requestBody } from '../data/state.js';
import { progressNote, runsLeft } from '../data/timing.js';
import { banner, download, el } from '../draw/dom.js';
import { Plots } from '../draw/plots.js';
import { Form } from './form.js';
import { renderRuns } from './runs.js';
import { SectionPanel } from './section.js';
import { TrajectoryPanel } from './trajectory.js';
import { customized, experiment, presetSwitched, sceneOpened, startedFrom, systemSwitched } from './transitions.js';

const $ = (id) => document.getElementById(id);

export class ExploreView {
  /** The view in `root` (its elements are found by id); `onShown()` asks the page to show
   *  this view (a scene opened from another view). */
  constructor(root, { catalog, onShown }) {
    this.root = root;
    this.catalog = catalog;
    this.onShown = onShown;
    this.form = new Form(catalog);
    const panel = { catalog, caption: (scene) => sceneCaption(scene, catalog), stem: (scene) => sceneStem(scene, catalog) };
    this.plots = new Plots($('plots'), panel);
    this.trajectory = new TrajectoryPanel($('dynamics'), panel);
    this.section = new SectionPanel($('dynamics'), panel);
    this.result = null;
    this.controller = null;
    this.frame = 0;
    this.stepNote = ''; // what an empty Step field ran with, for the status
    this.#experimentButtons();
    this.#wire();
  }

  /** Fills the form from a URL's query; the warnings of what it could not read. */
  restore(search) {
    const { state, warnings } = decodeState(search, this.catalog);
    this.fill(state);
    return { state, warnings };
  }

  /** Puts a state in the form. */
  fill(state) {
    this.form.fill(state);
    this.#syncDynamics();
  }

  /** The view's URL: the form's scene, not to be run on load. */
  url() {
    return `?${encodeState({ ...this.form.read().state, run: false }, this.catalog)}`;
  }

  show() {}

  /** The form's scene written in the URL (`run`: to be run on load). */
  syncURL(run = false) {
    history.replaceState(null, '', `?${encodeState({ ...this.form.read().state, run }, this.catalog)}`);
  }

  /** A scorecard cell (its scene, with the scorecard's methods) or a map cell (its /simulate
   *  body, with its one method), run here; what the scene leaves out comes from its preset. */
  open(scene, methods) {
    this.form.fill(sceneOpened(this.catalog, scene, methods));
    this.onShown();
    this.run();
  }

  /** Runs the form's scene: the stream drawn as it arrives. */
  async run() {
    const { form, section, trajectory } = this;
    form.clearErrors();
    section.showError(null);
    $('run-error').hidden = true;
    const { state, invalid } = form.read();
    if (invalid.length) {
      for (const e of invalid) form.showError(e.path, e.message);
      this.#status('error', 'Fix the marked fields, then run again.');
      this.#markStale(true);
      form.focusFirstError();
      return;
    }
    this.controller?.abort();
    const mine = new AbortController();
    this.controller = mine;
    this.syncURL(true);
    this.#setBusy(true);
    this.#progress(0);
    this.#status('running', 'Starting…');
    $('scene-class').hidden = true;
    this.#showResults();
    this.stepNote = '';
    this.#syncDynamics();
    const body = { ...requestBody(state, this.catalog), ...trajectory.request(), ...section.request() };
    const end = { finished: false, shutdown: null };
    try {
      // A busy server (503) is waited out as the other views do.
      await retrying(
        () => simulate(body, { signal: mine.signal, onEvent: (name, data) => this.controller === mine && this.#event(name, data, state, end) }),
        (wait) => this.#status('running', `Server busy, retrying in ${wait} s…`),
        mine.signal,
      );
      if (this.controller === mine) this.#ended(end);
    } catch (e) {
      if (this.controller === mine) this.#failed(e);
    } finally {
      if (this.controller === mine) this.#settled();
    }
  }

  // One event of the stream.
  #event(name, data, state, end) {
    if (name === 'scene') this.#scene(data, state);
    else if (name === 'progress') this.result?.progress(data);
    else if (name === 'points') this.result?.addPoints(data);
    else if (name === 'observables') this.result?.addObservables(data);
    else if (name === 'section') this.result?.addSection(data);
    else if (name === 'run') this.result?.finishRun(data);
    else if (name === 'done') end.finished = true;
    else if (name === 'shutdown') end.shutdown = data;
    this.#schedule();
  }

  // The scene a run's stream starts with: a new Result, and the plots reset for it.
  #scene(data, state) {
    this.#markStale(false);
    this.result = new Result(data);
    this.plots.reset(this.result);
    this.trajectory.reset(this.result);
    this.section.reset(this.result);
    $('scene-class').textContent = paperClassLine(data.paper_class);
    $('scene-class').dataset.member = String(Boolean(data.paper_class?.member));
    $('scene-class').hidden = !data.paper_class;
    $('download-json').disabled = false;
    $('download-csv').disabled = false;
    // An empty Step field runs the preset's (or the server's) step: say which.
    if (state.step === null && Number.isFinite(data.step)) {
      this.stepNote = ` with h = ${data.step}, ${state.preset ? 'the preset’s step' : 'the default step'} (the Step field is empty)`;
    }
    this.#status('running', `Running${this.stepNote}…`);
  }

  // The stream ended: done, or cut short by a shutdown or a broken connection.
  #ended({ finished, shutdown }) {
    const { result, stepNote } = this;
    if (finished) {
      const failed = result ? result.runs.filter((r) => r.status === 'failed').length : 0;
      const total = result ? result.runs.length : 0;
      this.#status(failed ? 'done-failed' : 'done', failed ? `Done${stepNote}: ${failed} of ${total} runs failed (see below).` : `Done${stepNote}: ${total} runs.`);
      return;
    }
    result?.interrupt('interrupted');
    this.#status('error', shutdown ? 'The server shut down during the run.' : 'The server closed the stream before the end.');
    banner(
      $('run-error'),
      shutdown
        ? 'The server is shutting down (it was stopped). The curves show what arrived; run again once it is back.'
        : 'The stream ended early: the server stopped or the connection broke. The curves show what arrived.',
    );
  }

  // Cancelled, refused (a field named, placed in the form where it can be) or disconnected.
  #failed(e) {
    if (e.name === 'AbortError') {
      this.result?.interrupt('cancelled');
      this.#status('cancelled', 'Cancelled.');
    } else if (e instanceof ApiError) {
      const placed = this.form.showError(e.path, e.message) || this.section.showError(e.path, e.message);
      const where = e.path ? ` (field “${fieldLabel(e.path)}”)` : '';
      this.#status('error', placed ? 'The server rejected a field: see the form.' : 'The server rejected the request.');
      banner($('run-error'), `${e.message}${where}`);
      // Nothing of this request ran: what the page shows is an earlier run's.
      this.#markStale(true);
      if (placed) this.form.focusFirstError();
    } else {
      this.result?.interrupt('interrupted');
      this.#status('error', 'The connection failed.');
      banner($('run-error'), `The connection failed: ${e.message}. The curves show what arrived.`);
    }
  }

  // The last request settled, whichever way.
  #settled() {
    this.controller = null;
    this.#setBusy(false);
    this.#draw();
    // The Run button was disabled while the run went, which leaves the focus nowhere: it goes
    // to the results, unless an invalid field took it.
    if (document.activeElement === document.body || !document.activeElement) $('results-title').focus({ preventScroll: true });
    // The height held for scrolling is let go once the results have arrived.
    $('status').closest('.results').style.minHeight = '';
  }

  // The paper's experiments (the catalog's paper scenes), each with the integrals its figures
  // show and its preset's running-mean window.
  #experimentButtons() {
    const buttons = paperExperiments(this.catalog).map((x) => {
      const b = el('button', 'experiment', x.label);
      b.type = 'button';
      b.dataset.system = x.system;
      b.dataset.preset = x.preset;
      b.addEventListener('click', () => {
        this.form.fill(experiment(this.catalog, x));
        this.run();
      });
      return b;
    });
    $('experiments').replaceChildren(...buttons);
  }

  #wire() {
    const { form } = this;
    form.el.addEventListener('submit', (e) => {
      e.preventDefault();
      this.run();
    });
    form.el.addEventListener('change', (e) => {
      const id = e.target.id;
      if (id === 'system') this.#switchSystem();
      else if (id === 'preset') form.fill(presetSwitched(this.catalog, form.read().state));
      else if (id === 'custom-start') this.#startFrom($('custom-start').value);
      form.renumber();
      this.#syncDynamics();
      if (['stat', 'smooth', 'window'].includes(id)) {
        this.plots.resetFloor();
        this.#draw();
      }
      this.syncURL();
    });
    $('add-method').addEventListener('click', () => {
      form.addMethod($('add-method-id').value);
      this.syncURL();
    });
    $('cancel').addEventListener('click', () => this.controller?.abort());
    const stem = () => sceneStem(this.result.scene, this.catalog);
    $('download-json').addEventListener('click', () => {
      if (this.result) download(`${stem()}.json`, 'application/json', JSON.stringify(this.result.toJSON(), null, 1));
    });
    $('download-csv').addEventListener('click', () => {
      if (this.result) download(`${stem()}.csv`, 'text/csv', this.result.toCSV());
    });
  }

  // A new system (transitions.js); "Custom system" opens the editor on the system shown.
  #switchSystem() {
    const { form, catalog } = this;
    if ($('system').value === CUSTOM) {
      if (form.shown !== CUSTOM) form.fill(customized(catalog, form.read({ as: form.shown }).state));
      return;
    }
    form.fill(systemSwitched(catalog, form.read().state, $('system').value));
  }

  // A "Start from" choice is `<form>:<system id>`.
  #startFrom(value) {
    if (!value) return;
    const [start, id] = value.split(':');
    this.form.fill(startedFrom(this.catalog, this.form.read().state, id, start));
    $('custom-start').value = value;
  }

  // The panels' pickers follow the form's system (its defaults when it changes).
  #syncDynamics() {
    const sys = dynamicsSystem(this.catalog, this.form.read().state.system);
    this.trajectory.setSystem(sys);
    this.section.setSystem(sys);
  }

  // Results of an earlier request, shown while the last one failed before it ran (a field
  // refused): dimmed, a line saying so, the downloads off, until a run starts.
  #markStale(stale) {
    const panel = $('status').closest('.results');
    const shown = Boolean(this.result);
    panel.classList.toggle('stale', stale && shown);
    $('stale-note').hidden = !(stale && shown);
    for (const id of ['download-json', 'download-csv']) $(id).disabled = stale || !shown;
  }

  // On a narrow screen the results sit under the form: bring them into view on Run, unless
  // the status line is already on screen. They get a screen's height first, so the page is
  // long enough to scroll them to the top before the plots arrive.
  #showResults() {
    const top = $('status').getBoundingClientRect().top;
    if (top >= 0 && top <= innerHeight - 100) return;
    const results = $('status').closest('.results');
    results.style.minHeight = `${innerHeight}px`;
    results.scrollIntoView({ block: 'start', behavior: 'smooth' });
  }

  #schedule() {
    if (!this.frame) this.frame = requestAnimationFrame(() => this.#draw());
  }

  #draw() {
    cancelAnimationFrame(this.frame);
    this.frame = 0;
    const { result } = this;
    if (!result) return;
    const window = Number($('window').value);
    this.plots.update({ stat: $('stat').value, window: $('smooth').checked && window > 0 ? window : 0 });
    this.#progress(result.fraction);
    renderRuns($('runs'), result, this.catalog);
    this.trajectory.update();
    this.section.update();
    if (this.controller) this.#status('running', `Running${this.stepNote}… ${progressNote(result.elapsed, runsLeft(result.runs))}.`);
  }

  #progress(fraction) {
    $('progress').value = fraction;
    $('progress-text').textContent = `${Math.floor(fraction * 100)}%`;
  }

  #status(state, text) {
    $('status').dataset.state = state;
    $('status').textContent = text;
  }

  #setBusy(busy) {
    $('run').disabled = busy;
    $('cancel').disabled = !busy;
    document.body.classList.toggle('busy', busy);
  }
}
