// The Section panel of Explore: a Poincaré section of each run, the two picked quantities at
// every crossing of surface = 0 in the chosen direction, one cloud of markers per run in its
// method's look. The surface is a formula (coordinates, velocities, t, parameters); the run
// sends it with the two quantities, so changing them takes another run, and the panel says
// so. A server error at `section.…` is shown under the panel's controls.
// The section is asked for only when its box is ticked: the server then evaluates the surface
// after every step, which takes a run up to 2–3 times as long.

import { el, option, textInput } from '../draw/dom.js';
import { sectionFor, xyColumns, xyCSV } from '../data/dynamics.js';
import { XYCard } from '../draw/xycard.js';
import { fill, picker } from './trajectory.js';

const DIRECTIONS = [
  ['up', 'upward (− to +)'],
  ['down', 'downward (+ to −)'],
  ['both', 'both ways'],
];

export class SectionPanel {
  /** As TrajectoryPanel's. */
  constructor(container, { catalog, caption, stem }) {
    this.catalog = catalog;
    this.caption = caption;
    this.stem = stem;
    this.card = new XYCard(container, { panel: 'section', title: 'Poincaré section', sub: 'at each crossing of surface = 0' });
    const surface = el('label', 'dyn-pick dyn-surface');
    this.surface = textInput('section-surface', '', 'surface formula');
    surface.append(el('span', '', 'surface'), this.surface);
    const direction = picker('section-direction', 'direction');
    this.direction = direction.select;
    this.direction.replaceChildren(...DIRECTIONS.map(([v, t]) => option(v, t)));
    this.x = picker('section-x', 'x axis');
    this.y = picker('section-y', 'y axis');
    this.error = el('p', 'field-error dyn-error');
    this.error.hidden = true;
    const on = el('label', 'dyn-pick dyn-on');
    this.on = el('input', 'section-on');
    this.on.type = 'checkbox';
    on.title = 'Each step is checked for a crossing: runs take up to 2–3 times as long.';
    on.append(this.on, el('span', '', 'compute with the next run'));
    this.card.controls.append(on, surface, direction.label, this.x.label, this.y.label, this.error);
    for (const input of [this.on, this.surface, this.direction, this.x.select, this.y.select]) {
      input.addEventListener('change', () => {
        this.showError(null);
        this.update();
      });
    }
    this.system = null;
    this.result = null;
    this.sent = null;
  }

  /** As TrajectoryPanel's: the system's defaults when it changed. */
  setSystem(sys) {
    if (this.system?.key === sys.key) return;
    this.system = sys;
    const d = sys.defaults.section;
    this.surface.value = d.surface;
    this.direction.value = d.direction;
    fill(this.x.select, sys.quantities, d.x);
    fill(this.y.select, sys.quantities, d.y);
    this.showError(null);
  }

  #picks() {
    return { on: this.on.checked, surface: this.surface.value, direction: this.direction.value, x: this.x.select.value, y: this.y.select.value };
  }

  /** The request's `section` (none unless ticked, nor without a surface). */
  request() {
    const picks = this.#picks();
    this.pending = null;
    if (!picks.on || !this.system?.quantities.length || !picks.surface.trim()) return {};
    this.pending = picks;
    return { section: sectionFor(picks) };
  }

  /** A server error: its message under the controls when its path is the section's. */
  showError(path, message) {
    const mine = typeof path === 'string' && path.startsWith('section');
    this.error.textContent = mine ? message : '';
    this.error.hidden = !mine;
    this.surface.classList.toggle('invalid', mine && path === 'section.surface');
    return mine;
  }

  reset(result) {
    this.result = result;
    this.sent = this.pending ?? null;
    this.card.clear();
    this.update();
  }

  update() {
    const result = this.result;
    if (!result) return;
    const sent = this.sent;
    const now = this.#picks();
    // What was computed is drawn; the note says when the controls ask for something else.
    const x = sent?.x ?? now.x;
    const y = sent?.y ?? now.y;
    const changed = now.on && (!sent || sent.surface !== now.surface || sent.direction !== now.direction || sent.x !== now.x || sent.y !== now.y);
    const where = sent ? `${sent.surface} = 0, ${sent.direction === 'both' ? 'both ways' : sent.direction}` : '';
    this.card.sub.textContent = sent ? `at each crossing of ${where}` : 'at each crossing of surface = 0';
    this.card.card.dataset.x = x;
    this.card.card.dataset.y = y;
    this.card.draw(result.runs, this.catalog, {
      columns: (run) => xyColumns(run, 'section', x, y),
      mode: 'points',
      xLabel: x,
      yLabel: y,
      empty: sent ? 'No crossing yet.' : 'No section was asked for: tick “compute with the next run” and run again.',
      describe: () => ({
        title: `Poincaré section: ${y} against ${x}`,
        caption: `${this.caption(result.scene)}${where ? `; crossings of ${where}` : ''}`,
        stem: `${this.stem(result.scene)}-section-${x}-${y}`,
        csv: () => xyCSV(result.runs, 'section', x, y),
      }),
    });
    if (changed) this.card.setNote('Run again to compute the section with the new settings; the plot shows the last run’s.');
  }
}
