// The page's wiring: load the catalog, restore the state from the URL, run a simulation on
// submit (or when the URL says run=1), feed the stream into a Result and redraw the plots,
// progress and runs table once per animation frame. Cancel aborts the fetch. Four more views,
// Scorecard, Paper, Work–precision and Map, live in the URL as `?view=scorecard` / `?view=paper` /
// `?view=work-precision` / `?view=map` (the last two with the form's scene); clicking a
// scorecard or map cell opens its scene here. "Custom system" in the system select opens the
// formula editor, filled from the system shown or from the built-in its "Start from" select
// picks, in the paper's form or the general one (the form's moves between states are in
// transitions.js). The results say whether the scene's system is in the paper's class. Under
// the error plots, the Trajectory and Section panels draw each run's observables and its
// Poincaré section, which the run asks for with the panels' picks.

import 'uplot/dist/uPlot.min.css';
import './style.css';
import { ApiError, fetchCatalog, retrying, simulate } from './api.js';
import { Form } from './form.js';
import { PaperView } from './paper.js';
import { ScorecardView } from './scorecard.js';
import { WorkPrecisionView } from './workprecision.js';
import { MapView } from './map.js';
import { Plots } from './plots.js';
import { Result } from './result.js';
import { renderRuns } from './runs.js';
import { paperClassLine, paperExperiments } from './catalog.js';
import { CUSTOM, sceneCaption, sceneStem } from './custom.js';
import { decodeState, encodeState, requestBody } from './state.js';
import { customized, experiment, presetSwitched, sceneOpened, startedFrom, systemSwitched } from './transitions.js';
import { download } from './dom.js';
import { fieldLabel } from './labels.js';
import { progressNote, runsLeft } from './timing.js';
import { dynamicsSystem } from './dynamics.js';
import { TrajectoryPanel } from './trajectory.js';
import { SectionPanel } from './section.js';

const $ = (id) => document.getElementById(id);

let catalog;
let form;
let plots;
let trajectory;
let section;
let result = null;
let controller = null;
let frame = 0;
let stepNote = ''; // what an empty Step field ran with, for the status
let view = 'main';
const views = {};

async function start() {
  try {
    catalog = await fetchCatalog();
  } catch (e) {
    banner($('load-error'), `Could not load the systems from the server: ${e.message}. Reload to retry.`);
    $('run').disabled = true;
    return;
  }
  form = new Form(catalog);
  plots = new Plots($('plots'), { catalog, caption: (scene) => sceneCaption(scene, catalog), stem: (scene) => sceneStem(scene, catalog) });
  const panel = { catalog, caption: (scene) => sceneCaption(scene, catalog), stem: (scene) => sceneStem(scene, catalog) };
  trajectory = new TrajectoryPanel($('dynamics'), panel);
  section = new SectionPanel($('dynamics'), panel);
  experimentButtons();
  const { state, warnings } = decodeState(location.search, catalog);
  form.fill(state);
  syncDynamics();
  if (warnings.length) banner($('load-error'), warnings.join('; '));
  wire();
  views.scorecard = new ScorecardView($('view-scorecard'), { catalog, onOpen: openScene });
  views.paper = new PaperView($('view-paper'), { catalog });
  views['work-precision'] = new WorkPrecisionView($('view-work-precision'), {
    read: () => form.read(),
    catalog,
    onFormError: (path, message) => {
      form.clearErrors();
      return form.showError(path, message);
    },
  });
  views.map = new MapView($('view-map'), {
    read: () => form.read(),
    fill: (state) => form.fill(state),
    catalog,
    onOpen: (body) => openScene(body, body.methods ?? []),
    onFormError: (path, message) => {
      form.clearErrors();
      return form.showError(path, message);
    },
    onEdit: () => setView('main', true),
  });
  const wanted = new URLSearchParams(location.search).get('view');
  if (Object.hasOwn(views, wanted ?? '')) {
    setView(wanted);
  } else {
    setView('main');
    if (state.run) run();
    else syncURL();
  }
}

// Shows one view; `push` adds a history entry (a tab click), else the URL stays.
function setView(name, push = false) {
  view = Object.hasOwn(views, name) ? name : 'main';
  $('view-main').hidden = view !== 'main';
  for (const [id, v] of Object.entries(views)) v.root.hidden = id !== view;
  for (const tab of document.querySelectorAll('.tabs .tab')) {
    tab.classList.toggle('active', tab.dataset.view === view);
    if (tab.dataset.view === view) tab.setAttribute('aria-current', 'page');
    else tab.removeAttribute('aria-current');
  }
  if (push) {
    if (view === 'main') {
      const { state } = form.read();
      history.pushState(null, '', `?${encodeState({ ...state, run: false }, catalog)}`);
    } else history.pushState(null, '', `?view=${view}`);
  }
  // The work–precision and map views write their own URL (the form's scene with it) in show().
  views[view]?.show();
}

// A scorecard cell (its scene, with the scorecard's methods) or a map cell (its /simulate
// body, with its one method), run here; what the scene leaves out comes from its preset.
function openScene(scene, methods) {
  form.fill(sceneOpened(catalog, scene, methods));
  setView('main', true);
  run();
}

// The paper's experiments (the catalog's paper scenes), each with the integrals its figures
// show and its preset's running-mean window.
function experimentButtons() {
  const buttons = paperExperiments(catalog).map((x) => {
    const b = document.createElement('button');
    b.type = 'button';
    b.className = 'experiment';
    b.dataset.system = x.system;
    b.dataset.preset = x.preset;
    b.textContent = x.label;
    b.addEventListener('click', () => {
      form.fill(experiment(catalog, x));
      run();
    });
    return b;
  });
  $('experiments').replaceChildren(...buttons);
}

function wire() {
  for (const tab of document.querySelectorAll('.tabs .tab')) {
    tab.addEventListener('click', (e) => {
      e.preventDefault();
      if (tab.dataset.view !== view) setView(tab.dataset.view, true);
    });
  }
  window.addEventListener('popstate', () => {
    const wanted = new URLSearchParams(location.search).get('view');
    // The work–precision and map views' URLs carry the form's scene: restore it with the view.
    if (wanted === 'work-precision' || wanted === 'map') form.fill(decodeState(location.search, catalog).state);
    if (wanted === 'map') views.map.restore(location.search);
    if (Object.hasOwn(views, wanted ?? '')) setView(wanted);
    else {
      form.fill(decodeState(location.search, catalog).state);
      syncDynamics();
      setView('main');
    }
  });
  form.el.addEventListener('submit', (e) => {
    e.preventDefault();
    run();
  });
  // The skip link lands on Run, past the form's fields.
  document.querySelector('.skip-link')?.addEventListener('click', (e) => {
    e.preventDefault();
    setView('main');
    $('run').scrollIntoView({ block: 'center' });
    $('run').focus({ preventScroll: true });
  });
  form.el.addEventListener('change', (e) => {
    const id = e.target.id;
    if (id === 'system') switchSystem();
    else if (id === 'preset') form.fill(presetSwitched(catalog, form.read().state));
    else if (id === 'custom-start') startFrom($('custom-start').value);
    form.renumber();
    syncDynamics();
    if (['stat', 'smooth', 'window'].includes(id)) {
      plots.resetFloor();
      draw();
    }
    syncURL();
  });
  $('add-method').addEventListener('click', () => {
    form.addMethod($('add-method-id').value);
    syncURL();
  });
  $('cancel').addEventListener('click', () => controller?.abort());
  $('download-json').addEventListener('click', () => {
    if (result) download(`${sceneStem(result.scene, catalog)}.json`, 'application/json', JSON.stringify(result.toJSON(), null, 1));
  });
  $('download-csv').addEventListener('click', () => {
    if (result) download(`${sceneStem(result.scene, catalog)}.csv`, 'text/csv', result.toCSV());
  });
}

// A new system (transitions.js); "Custom system" opens the editor on the system shown.
function switchSystem() {
  if ($('system').value === CUSTOM) {
    if (form.shown !== CUSTOM) form.fill(customized(catalog, form.read({ as: form.shown }).state));
    return;
  }
  form.fill(systemSwitched(catalog, form.read().state, $('system').value));
}

// A "Start from" choice is `<form>:<system id>`.
function startFrom(value) {
  if (!value) return;
  const [start, id] = value.split(':');
  form.fill(startedFrom(catalog, form.read().state, id, start));
  $('custom-start').value = value;
}

// The panels' pickers follow the form's system (its defaults when it changes).
function syncDynamics() {
  const sys = dynamicsSystem(catalog, form.read().state.system);
  trajectory.setSystem(sys);
  section.setSystem(sys);
}

function syncURL(run = false) {
  const { state } = form.read();
  history.replaceState(null, '', `?${encodeState({ ...state, run }, catalog)}`);
}

async function run() {
  form.clearErrors();
  section.showError(null);
  $('run-error').hidden = true;
  const { state, invalid } = form.read();
  if (invalid.length) {
    for (const e of invalid) form.showError(e.path, e.message);
    status('error', 'Fix the marked fields, then run again.');
    markStale(true);
    form.focusFirstError();
    return;
  }
  controller?.abort();
  const mine = new AbortController();
  controller = mine;
  syncURL(true);
  setBusy(true);
  progress(0);
  status('running', 'Starting…');
  $('scene-class').hidden = true;
  showResults();
  let finished = false;
  let shutdown = null;
  stepNote = '';
  syncDynamics();
  const body = { ...requestBody(state, catalog), ...trajectory.request(), ...section.request() };
  try {
    // A busy server (503) is waited out as the other views do.
    await retrying(() => simulate(body, {
      signal: mine.signal,
      onEvent: (name, data) => {
        if (controller !== mine) return;
        if (name === 'scene') {
          markStale(false);
          result = new Result(data);
          plots.reset(result);
          trajectory.reset(result);
          section.reset(result);
          $('scene-class').textContent = paperClassLine(data.paper_class);
          $('scene-class').dataset.member = String(Boolean(data.paper_class?.member));
          $('scene-class').hidden = !data.paper_class;
          $('download-json').disabled = false;
          $('download-csv').disabled = false;
          // An empty Step field runs the preset's (or the server's) step: say which.
          if (state.step === null && Number.isFinite(data.step)) {
            stepNote = ` with h = ${data.step}, ${state.preset ? 'the preset’s step' : 'the default step'} (the Step field is empty)`;
          }
          status('running', `Running${stepNote}…`);
        } else if (name === 'progress') result?.progress(data);
        else if (name === 'points') result?.addPoints(data);
        else if (name === 'observables') result?.addObservables(data);
        else if (name === 'section') result?.addSection(data);
        else if (name === 'run') result?.finishRun(data);
        else if (name === 'done') finished = true;
        else if (name === 'shutdown') shutdown = data;
        schedule();
      },
    }), (wait) => status('running', `Server busy, retrying in ${wait} s…`), mine.signal);
    if (controller !== mine) return;
    if (finished) {
      const failed = result ? result.runs.filter((r) => r.status === 'failed').length : 0;
      const total = result ? result.runs.length : 0;
      status(failed ? 'done-failed' : 'done', failed ? `Done${stepNote}: ${failed} of ${total} runs failed (see below).` : `Done${stepNote}: ${total} runs.`);
    } else if (shutdown) {
      result?.interrupt('interrupted');
      status('error', 'The server shut down during the run.');
      banner($('run-error'), 'The server is shutting down (it was stopped). The curves show what arrived; run again once it is back.');
    } else {
      result?.interrupt('interrupted');
      status('error', 'The server closed the stream before the end.');
      banner($('run-error'), 'The stream ended early: the server stopped or the connection broke. The curves show what arrived.');
    }
  } catch (e) {
    if (controller !== mine) return;
    if (e.name === 'AbortError') {
      result?.interrupt('cancelled');
      status('cancelled', 'Cancelled.');
    } else if (e instanceof ApiError) {
      const placed = form.showError(e.path, e.message) || section.showError(e.path, e.message);
      const where = e.path ? ` (field “${fieldLabel(e.path)}”)` : '';
      status('error', placed ? 'The server rejected a field: see the form.' : 'The server rejected the request.');
      banner($('run-error'), `${e.message}${where}`);
      // Nothing of this request ran: what the page shows is an earlier run's.
      markStale(true);
      if (placed) form.focusFirstError();
    } else {
      result?.interrupt('interrupted');
      status('error', 'The connection failed.');
      banner($('run-error'), `The connection failed: ${e.message}. The curves show what arrived.`);
    }
  } finally {
    if (controller === mine) {
      controller = null;
      setBusy(false);
      draw();
      // The Run button was disabled while the run went, which leaves the focus nowhere:
      // it goes to the results, unless an invalid field took it.
      if (document.activeElement === document.body || !document.activeElement) $('results-title').focus({ preventScroll: true });
      // The height held for scrolling is let go once the results have arrived.
      $('status').closest('.results').style.minHeight = '';
    }
  }
}

// Results of an earlier request, shown while the last one failed before it ran (a field
// refused): dimmed, a line saying so, the downloads off, until a run starts.
function markStale(stale) {
  const panel = $('status').closest('.results');
  const shown = Boolean(result);
  panel.classList.toggle('stale', stale && shown);
  $('stale-note').hidden = !(stale && shown);
  for (const id of ['download-json', 'download-csv']) $(id).disabled = stale || !shown;
}

// On a narrow screen the results sit under the form: bring them into view on Run, unless
// the status line is already on screen. They get a screen's height first, so the page is
// long enough to scroll them to the top before the plots arrive.
function showResults() {
  const top = $('status').getBoundingClientRect().top;
  if (top >= 0 && top <= innerHeight - 100) return;
  const results = $('status').closest('.results');
  results.style.minHeight = `${innerHeight}px`;
  results.scrollIntoView({ block: 'start', behavior: 'smooth' });
}

function schedule() {
  if (!frame) frame = requestAnimationFrame(draw);
}

function draw() {
  cancelAnimationFrame(frame);
  frame = 0;
  if (!result) return;
  const smooth = $('smooth').checked;
  const window = Number($('window').value);
  plots.update({ stat: $('stat').value, window: smooth && window > 0 ? window : 0 });
  progress(result.fraction);
  renderRuns($('runs'), result, catalog);
  trajectory.update();
  section.update();
  if (controller) status('running', `Running${stepNote}… ${progressNote(result.elapsed, runsLeft(result.runs))}.`);
}

function progress(fraction) {
  $('progress').value = fraction;
  $('progress-text').textContent = `${Math.floor(fraction * 100)}%`;
}

function status(state, text) {
  $('status').dataset.state = state;
  $('status').textContent = text;
}

function setBusy(busy) {
  $('run').disabled = busy;
  $('cancel').disabled = !busy;
  document.body.classList.toggle('busy', busy);
}

function banner(node, text) {
  node.textContent = text;
  node.hidden = false;
}

start();
