// The page: load the catalog, then show one view at a time, each a folder of its own —
// Explore (the form and a live run; the URL holds its scene), Scorecard, Paper,
// Work–precision and Map (`?view=scorecard`, `?view=paper`, `?view=work-precision`,
// `?view=map`, the last two with the form's scene). The tabs switch views with a history
// entry; Back and Forward restore them. A scorecard or map cell opens its scene in Explore.
// Modules are layered: `data/` (what the page knows) under `draw/` (what views draw with)
// under the views; no view imports another, they meet here.

import 'uplot/dist/uPlot.min.css';
import './style.css';
import { fetchCatalog } from './data/api.js';
import { decodeState } from './data/state.js';
import { banner } from './draw/dom.js';
import { ExploreView } from './explore/view.js';
import { MapView } from './map/view.js';
import { PaperView } from './paper/view.js';
import { ScorecardView } from './scorecard/view.js';
import { WorkPrecisionView } from './workprecision/view.js';

const $ = (id) => document.getElementById(id);

/** The Explore view's name in the tabs and the history. */
const EXPLORE = 'main';

const views = {};
let view = EXPLORE;

async function start() {
  let catalog;
  try {
    catalog = await fetchCatalog();
  } catch (e) {
    banner($('load-error'), `Could not load the systems from the server: ${e.message}. Reload to retry.`);
    $('run').disabled = true;
    return;
  }
  const explore = new ExploreView($('view-main'), { catalog, onShown: () => setView(EXPLORE, true) });
  const { state, warnings } = explore.restore(location.search);
  if (warnings.length) banner($('load-error'), warnings.join('; '));
  // The views that compute from the form's scene read it and place a refused field in it.
  const formError = (path, message) => {
    explore.form.clearErrors();
    return explore.form.showError(path, message);
  };
  const read = () => explore.form.read();
  views[EXPLORE] = explore;
  views.scorecard = new ScorecardView($('view-scorecard'), { catalog, onOpen: (scene, methods) => explore.open(scene, methods) });
  views.paper = new PaperView($('view-paper'), { catalog });
  views['work-precision'] = new WorkPrecisionView($('view-work-precision'), { read, catalog, onFormError: formError });
  views.map = new MapView($('view-map'), {
    read,
    fill: (s) => explore.fill(s),
    catalog,
    onOpen: (body) => explore.open(body, body.methods ?? []),
    onFormError: formError,
    onEdit: () => setView(EXPLORE, true),
  });
  wire(explore, catalog);
  const wanted = new URLSearchParams(location.search).get('view');
  if (wanted !== EXPLORE && Object.hasOwn(views, wanted ?? '')) {
    setView(wanted);
  } else {
    setView(EXPLORE);
    if (state.run) explore.run();
    else explore.syncURL();
  }
}

// Shows one view; `push` adds a history entry (a tab click), else the URL stays. The
// work–precision and map views write their own URL (the form's scene with it) in show().
function setView(name, push = false) {
  view = Object.hasOwn(views, name) ? name : EXPLORE;
  for (const [id, v] of Object.entries(views)) v.root.hidden = id !== view;
  for (const tab of document.querySelectorAll('.tabs .tab')) {
    tab.classList.toggle('active', tab.dataset.view === view);
    if (tab.dataset.view === view) tab.setAttribute('aria-current', 'page');
    else tab.removeAttribute('aria-current');
  }
  if (push) history.pushState(null, '', view === EXPLORE ? views[EXPLORE].url() : `?view=${view}`);
  views[view].show();
}

function wire(explore, catalog) {
  for (const tab of document.querySelectorAll('.tabs .tab')) {
    tab.addEventListener('click', (e) => {
      e.preventDefault();
      if (tab.dataset.view !== view) setView(tab.dataset.view, true);
    });
  }
  window.addEventListener('popstate', () => {
    const wanted = new URLSearchParams(location.search).get('view');
    // The work–precision and map views' URLs carry the form's scene: restore it with the view.
    if (wanted === 'work-precision' || wanted === 'map') explore.fill(decodeState(location.search, catalog).state);
    if (wanted === 'map') views.map.restore(location.search);
    if (wanted !== EXPLORE && Object.hasOwn(views, wanted ?? '')) setView(wanted);
    else {
      explore.restore(location.search);
      setView(EXPLORE);
    }
  });
  // The skip link lands on Run, past the form's fields.
  document.querySelector('.skip-link')?.addEventListener('click', (e) => {
    e.preventDefault();
    setView(EXPLORE);
    $('run').scrollIntoView({ block: 'center' });
    $('run').focus({ preventScroll: true });
  });
}

start();
