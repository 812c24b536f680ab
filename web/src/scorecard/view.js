// The Scorecard view: posts `/scorecard` (every method × the paper's six scenes and the
// literature's seven) and shows two grids, a row per method in each: the method's measured
// properties (reversible, symmetric, preserves the fibration) per system, and the verdict of
// each integral's error per scene, the scenes grouped by system, each cell coloured by its
// verdict. A method that has no step for a system (one made for the paper's class alone, on
// a system outside it) is marked "n/a" with the reason on hover, not as a failure. Clicking a
// verdict opens that scene in the main view with the scorecard's methods that apply to it.

import { ApiError, fetchScorecard, retrying } from '../data/api.js';
import { findPreset, findSystem, panelTitles, paperClassLine, presetLabel, systemShortName } from '../data/catalog.js';
import { INTEGRAL_NAME, INTEGRAL_SHORT, MARKS, PROPERTIES, VERDICTS, notApplicable, propertyMark, sceneIntegrals, systemsOf, verdictTitle } from '../data/verdicts.js';
import { el } from '../draw/dom.js';
import { humanLabel } from '../data/labels.js';
import { gridKeys } from './gridkeys.js';

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
    this.#status('running', 'Computing the scorecard: every method on the paper’s and the literature’s scenes…');
    try {
      this.card = await retrying(
        () => fetchScorecard({}, { signal: mine.signal }),
        (wait) => this.#status('running', `The server is busy; retrying in ${wait} s…`),
        mine.signal,
      );
      if (this.controller !== mine) return;
      this.render();
      const runs = this.card.scenes.flatMap((s) => s.runs);
      const failed = runs.filter((r) => r.status === 'failed').length;
      const na = runs.filter(notApplicable).length;
      const extra = [failed ? `${failed} failed` : '', na ? `${na} not applicable` : ''].filter(Boolean).join(', ');
      this.#status(failed ? 'done-failed' : 'done', `Done: ${runs.length - na} runs on ${this.card.scenes.length} scenes${extra ? ` (${extra})` : ''}. Click a cell to open its scene.`);
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
    const item = (className, mark, text) => {
      const i = el('span', 'legend-item');
      i.append(el('span', className, mark), ` ${text}`);
      return i;
    };
    this.legend.replaceChildren(
      ...VERDICTS.map((v) => item(`verdict-cell ${v.kind}`, v.letter, `${v.label}: ${v.text}`)),
      item('verdict-cell not_applicable', 'n/a', 'the method does not apply to the system'),
      item('verdict-cell none', '–', 'no verdict (no data)'),
      el('p', 'criterion', `Criterion: ${card.criterion}`),
      el('p', 'criterion', `Properties: ${card.properties_test}`),
    );
    const verdicts = this.#verdicts();
    gridKeys(verdicts, 'td.verdict-cell[tabindex]');
    verdicts.setAttribute('aria-label', 'Verdicts, per scene: arrow keys move between cells, Enter opens a scene');
    const scroll = (table) => {
      const box = el('div', 'scorecard-scroll');
      box.append(table);
      return box;
    };
    this.hint = el('p', 'scroll-hint', 'More scenes to the right: scroll sideways; the method column stays.');
    this.hint.hidden = true;
    this.grid.replaceChildren(
      el('h3', 'scorecard-caption', 'Properties, per system'),
      scroll(this.#properties()),
      el('h3', 'scorecard-caption', 'Verdicts, per scene'),
      this.hint,
      scroll(verdicts),
    );
    this.#cue();
    if (!this.resize) {
      this.resize = new ResizeObserver(() => this.#cue());
      this.resize.observe(this.grid);
    }
  }

  // Whether the tables are wider than their box: then a line says more scenes follow, and the
  // boxes show a shadow on the side that scrolls.
  #cue() {
    const boxes = [...this.grid.querySelectorAll('.scorecard-scroll')];
    for (const box of boxes) box.dataset.overflow = String(box.scrollWidth > box.clientWidth + 1);
    if (this.hint) this.hint.hidden = !boxes.some((b) => b.dataset.overflow === 'true');
  }

  // A row per method; per system, a mark per property.
  #properties() {
    const card = this.card;
    const systems = systemsOf(card);
    const [head1, head2] = [el('tr'), el('tr')];
    head1.append(methodHead(2));
    for (const [id] of systems) {
      const system = findSystem(this.catalog, id);
      const th = el('th', 'group', systemShortName(system) || id);
      th.colSpan = PROPERTIES.length;
      th.title = [system?.name ?? id, paperClassLine(system?.paper_class)].filter(Boolean).join(': ');
      head1.append(th);
      for (const p of PROPERTIES) {
        const h = el('th', 'prop-head', p.short);
        h.title = `${p.name} on ${system?.name ?? id}`;
        head2.append(h);
      }
    }
    const body = card.methods.map((m, mi) => {
      const tr = methodRow(m);
      for (const [system] of systems) {
        for (const p of PROPERTIES) {
          const { mark, title } = propertyMark(card, mi, system, p.id);
          const td = el('td', `prop ${mark}`, MARKS[mark][0]);
          td.title = title;
          Object.assign(td.dataset, { property: p.id, system, mark });
          tr.append(td);
        }
      }
      return tr;
    });
    return table('scorecard scorecard-properties', [head1, head2], body);
  }

  // A row per method; per scene (grouped by system), a verdict per integral.
  #verdicts() {
    const card = this.card;
    const [head1, head2, head3] = [el('tr'), el('tr'), el('tr')];
    head1.append(methodHead(3));
    const groups = systemGroups(card.scenes);
    // A narrow empty column before each scene keeps the groups and scenes apart.
    for (const group of groups) {
      const system = findSystem(this.catalog, group.system);
      const th = el('th', 'group', systemShortName(system) || group.system);
      th.colSpan = group.scenes.reduce((n, s) => n + sceneIntegrals(s).length, group.scenes.length - 1);
      th.title = system?.name ?? group.system;
      head1.append(el('th', 'gap'), th);
      const titles = sceneTitles(this.catalog, group.scenes);
      group.scenes.forEach((s, i) => {
        const h = el('th', 'scene-head', titles[i]);
        h.colSpan = sceneIntegrals(s).length;
        h.title = [s.id, paperClassLine(s.scene.paper_class)].filter(Boolean).join(': ');
        head2.append(el('th', 'gap'), h);
        head3.append(el('th', 'gap'));
        for (const integral of sceneIntegrals(s)) {
          const ih = el('th', 'integral-head', INTEGRAL_SHORT[integral] ?? integral);
          ih.title = INTEGRAL_NAME[integral] ?? integral;
          head3.append(ih);
        }
      });
    }
    const body = card.methods.map((m, mi) => {
      const tr = methodRow(m);
      for (const s of card.scenes) {
        tr.append(el('td', 'gap'));
        for (const integral of sceneIntegrals(s)) tr.append(this.#cell(m, s, s.runs[mi], integral));
      }
      return tr;
    });
    return table('scorecard scorecard-verdicts', [head1, head2, head3], body);
  }

  // A run's verdict on an integral; "n/a" for a method without a step for the system.
  #cell(m, s, run, integral) {
    const who = `${humanLabel(m.label)}, ${s.id}`;
    if (notApplicable(run)) {
      const td = el('td', 'verdict-cell not_applicable', 'n/a');
      td.title = `${who}: not applicable${run.error ? `: ${run.error}` : ''}`;
      Object.assign(td.dataset, { scene: s.id, integral, kind: 'not_applicable' });
      return td;
    }
    const v = run?.verdicts?.[integral];
    const kind = v?.kind ?? 'none';
    const td = el('td', `verdict-cell ${kind}`, VERDICTS.find((x) => x.kind === kind)?.letter ?? '–');
    const failed = run?.status === 'failed' ? ` (run failed: ${run.error})` : '';
    td.title = verdictTitle(v, `${who}, ${INTEGRAL_NAME[integral] ?? integral}${failed}: `);
    Object.assign(td.dataset, { scene: s.id, integral, kind });
    // Focusable, one Tab stop for the table (gridKeys): Enter opens the scene.
    td.tabIndex = -1;
    td.addEventListener('click', () => this.onOpen(s.scene, this.card.methods.filter((_, i) => !notApplicable(s.runs[i]))));
    return td;
  }

  #status(state, text) {
    this.status.dataset.state = state;
    this.status.textContent = text;
  }
}

/** Consecutive scenes of one system, in order: [{system, scenes}]. */
export function systemGroups(scenes) {
  const groups = [];
  for (const s of scenes) {
    const last = groups[groups.length - 1];
    if (last?.system === s.scene.system) last.scenes.push(s);
    else groups.push({ system: s.scene.system, scenes: [s] });
  }
  return groups;
}

/**
 * The column heads of one system's scenes: each preset's label without "Paper: " and without
 * what every label of the group starts with (`panelTitles`); a label far wider than its
 * columns gives way to the preset's id (the label is on hover). A repeated scene adds its
 * index.
 */
export function sceneTitles(catalog, scenes) {
  const presets = scenes.map((s) => findPreset(findSystem(catalog, s.scene.system), s.scene.preset));
  const titles = panelTitles(presets.map((p, i) => (p ? presetLabel(p) : scenes[i].id)));
  return titles.map((title, i) => {
    const s = scenes[i];
    const room = 7 * sceneIntegrals(s).length;
    const short = title.length > room && presets[i] ? presets[i].id : title;
    return s.id.includes('#') ? `${short} (${s.id.split('#')[1]})` : short;
  });
}

function methodHead(rows) {
  const th = el('th', 'method-head', 'Method');
  th.rowSpan = rows;
  th.scope = 'col';
  return th;
}

function methodRow(m) {
  const tr = el('tr');
  tr.dataset.method = m.label;
  tr.append(el('th', 'method', humanLabel(m.label)));
  return tr;
}

function table(className, heads, rows) {
  const t = el('table', className);
  const thead = el('thead');
  thead.append(...heads);
  const tbody = el('tbody');
  tbody.append(...rows);
  t.append(thead, tbody);
  return t;
}
