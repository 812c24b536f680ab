// The Scorecard view: posts `/scorecard` (every method × the paper's six scenes) and shows
// a grid — a row per method, a column per scene and integral, each cell coloured by its
// verdict — with the method's measured properties (reversible, preserves the fibration) per
// system beside it, a legend and the server's criterion. Clicking a cell opens that scene
// in the main view with the scorecard's methods.

import { ApiError, fetchScorecard, retrying } from './api.js';
import { findPreset, findSystem, presetLabel, systemShortName } from './catalog.js';
import { INTEGRAL_NAME, INTEGRAL_SHORT, VERDICTS, propertyMark, sceneIntegrals, systemsOf, verdictTitle } from './verdicts.js';
import { el } from './dom.js';
import { humanLabel } from './labels.js';

export class ScorecardView {
  /** `onOpen(scene, methods)`: show a scene's plots in the main view. */
  constructor(root, { onOpen, catalog }) {
    this.root = root;
    this.onOpen = onOpen;
    this.catalog = catalog;
    this.card = null;
    this.controller = null;
    this.status = root.querySelector('.view-status');
    this.grid = root.querySelector('.scorecard-grid');
    this.legend = root.querySelector('.scorecard-legend');
    root.querySelector('.scorecard-run').addEventListener('click', () => this.load());
  }

  /** Computes the scorecard once (again on the button). */
  show() {
    if (!this.card && !this.controller) this.load();
  }

  async load() {
    this.controller?.abort();
    const mine = new AbortController();
    this.controller = mine;
    this.#status('running', 'Computing the scorecard: every method on the paper’s scenes…');
    try {
      this.card = await retrying(
        () => fetchScorecard({}, { signal: mine.signal }),
        (wait) => this.#status('running', `The server is busy; retrying in ${wait} s…`),
        mine.signal,
      );
      if (this.controller !== mine) return;
      this.render();
      const runs = this.card.scenes.reduce((n, s) => n + s.runs.length, 0);
      const failed = this.card.scenes.reduce((n, s) => n + s.runs.filter((r) => r.status !== 'ok').length, 0);
      this.#status(failed ? 'done-failed' : 'done', `Done: ${runs} runs on ${this.card.scenes.length} scenes${failed ? `, ${failed} failed` : ''}. Click a cell to open its scene.`);
    } catch (e) {
      if (this.controller !== mine || e.name === 'AbortError') return;
      const where = e instanceof ApiError && e.path ? ` (field ${e.path})` : '';
      this.#status('error', `The scorecard failed: ${e.message}${where}`);
    } finally {
      if (this.controller === mine) this.controller = null;
    }
  }

  render() {
    const card = this.card;
    this.legend.replaceChildren(
      ...VERDICTS.map((v) => {
        const item = el('span', 'legend-item');
        item.append(el('span', `verdict-cell ${v.kind}`, v.letter), ` ${v.label}: ${v.text}`);
        return item;
      }),
      el('p', 'criterion', `Criterion: ${card.criterion}`),
      el('p', 'criterion', `Properties: ${card.properties_test}`),
    );
    const systems = systemsOf(card);
    const table = el('table', 'scorecard');
    const head1 = el('tr');
    const head2 = el('tr');
    const method = el('th', 'method-head', 'Method');
    method.rowSpan = 2;
    method.scope = 'col';
    const props = el('th', 'group', 'Reversible · fibration');
    props.colSpan = systems.length * 2;
    props.title = card.properties_test;
    head1.append(method, props);
    for (const [system] of systems) {
      for (const [short, long] of [['rev', 'reversible'], ['fib', 'preserves the fibration']]) {
        const th = el('th', 'prop-head', short);
        th.title = `${long} on ${system}`;
        const sub = el('small', '', systemShortName(findSystem(this.catalog, system)) || system);
        th.append(el('br'), sub);
        head2.append(th);
      }
    }
    for (const s of card.scenes) {
      // A narrow empty column between scenes keeps the groups apart.
      head1.append(el('th', 'gap'));
      head2.append(el('th', 'gap'));
      const th = el('th', 'group', sceneLabel(this.catalog, s));
      th.colSpan = sceneIntegrals(s).length;
      th.title = s.id;
      head1.append(th);
      for (const integral of sceneIntegrals(s)) {
        const h = el('th', 'integral-head', INTEGRAL_SHORT[integral] ?? integral);
        h.title = INTEGRAL_NAME[integral] ?? integral;
        head2.append(h);
      }
    }
    const thead = el('thead');
    thead.append(head1, head2);
    const tbody = el('tbody');
    card.methods.forEach((m, mi) => {
      const tr = el('tr');
      tr.dataset.method = m.label;
      tr.append(el('th', 'method', humanLabel(m.label)));
      for (const [system] of systems) {
        for (const property of ['reversible', 'preserves_fibration']) {
          const { mark, title } = propertyMark(card, mi, system, property);
          const td = el('td', `prop ${mark}`, { yes: '✓', no: '✗', mixed: '±', unknown: '?' }[mark]);
          td.title = title;
          td.dataset.property = property;
          td.dataset.system = system;
          td.dataset.mark = mark;
          tr.append(td);
        }
      }
      for (const s of card.scenes) {
        tr.append(el('td', 'gap'));
        const run = s.runs[mi];
        for (const integral of sceneIntegrals(s)) {
          const v = run?.verdicts?.[integral];
          const kind = v?.kind ?? 'none';
          const td = el('td', `verdict-cell ${kind}`, VERDICTS.find((x) => x.kind === kind)?.letter ?? '–');
          const failed = run?.status === 'failed' ? ` (run failed: ${run.error})` : '';
          td.title = verdictTitle(v, `${humanLabel(m.label)}, ${s.id}, ${INTEGRAL_NAME[integral] ?? integral}${failed}: `);
          Object.assign(td.dataset, { scene: s.id, integral, kind });
          td.tabIndex = 0;
          td.addEventListener('click', () => this.onOpen(s.scene, card.methods));
          td.addEventListener('keydown', (e) => {
            if (e.key === 'Enter') this.onOpen(s.scene, card.methods);
          });
          tr.append(td);
        }
      }
      tbody.append(tr);
    });
    table.append(thead, tbody);
    this.grid.replaceChildren(table);
  }

  #status(state, text) {
    this.status.dataset.state = state;
    this.status.textContent = text;
  }
}

/** A scene's column label: the preset's label without "Paper: ", else its id. */
export function sceneLabel(catalog, s) {
  const preset = findPreset(findSystem(catalog, s.scene.system), s.scene.preset);
  const label = preset ? presetLabel(preset) : s.id;
  return s.id.includes('#') ? `${label} (${s.id.split('#')[1]})` : label;
}
