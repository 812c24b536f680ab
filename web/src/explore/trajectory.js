// The Trajectory panel of Explore: one observable against t, or two against each other (a
// phase portrait), one curve per run in its method's look. The pickers offer the system's
// coordinates and their velocities; the run asks for all of them as observables (when they
// fit the API's limit), so a new pick redraws at once without running again.

import { el, option } from '../draw/dom.js';
import { TIME, observablesFor, xyColumns, xyCSV } from '../data/dynamics.js';
import { XYCard } from '../draw/xycard.js';

export class TrajectoryPanel {
  /** `catalog`: GET /systems; `caption(scene)`, `stem(scene)`: as the plots'. */
  constructor(container, { catalog, caption, stem }) {
    this.catalog = catalog;
    this.caption = caption;
    this.stem = stem;
    this.card = new XYCard(container, { panel: 'trajectory', title: 'Trajectory', sub: 'sampled at the “points” times' });
    this.x = picker('traj-x', 'x axis');
    this.y = picker('traj-y', 'y axis');
    this.card.controls.append(this.x.label, this.y.label);
    for (const s of [this.x.select, this.y.select]) s.addEventListener('change', () => this.update());
    this.system = null;
    this.result = null;
  }

  /** The form's system (dynamics.js `dynamicsSystem`): new pickers, and its default picks
   *  when the system changed. */
  setSystem(sys) {
    if (this.system?.key === sys.key) return;
    const keep = this.system && this.system.quantities.join() === sys.quantities.join();
    const was = { x: this.x.select.value, y: this.y.select.value };
    this.system = sys;
    fill(this.x.select, [TIME, ...sys.quantities], keep ? was.x : sys.defaults.trajectory.x);
    fill(this.y.select, sys.quantities, keep ? was.y : sys.defaults.trajectory.y);
  }

  /** The request's `observables`. */
  request() {
    if (!this.system?.quantities.length) return {};
    return { observables: observablesFor(this.system.quantities, [this.x.select.value, this.y.select.value]) };
  }

  reset(result) {
    this.result = result;
    this.card.clear();
    this.update();
  }

  update() {
    const result = this.result;
    if (!result) return;
    const x = this.x.select.value;
    const y = this.y.select.value;
    const versus = x === TIME ? `${y} against t` : `${y} against ${x}`;
    this.card.card.dataset.x = x;
    this.card.card.dataset.y = y;
    this.card.draw(result.runs, this.catalog, {
      columns: (run) => xyColumns(run, 'observables', x, y),
      mode: 'lines',
      xLabel: x,
      yLabel: y,
      empty: result.runs.some((r) => r.observables) ? `This run has no ${[x, y].filter((n) => n !== TIME).join(' or ')}: run again to draw it.` : 'No samples yet.',
      describe: () => ({
        title: x === TIME ? `Trajectory: ${versus}` : `Phase portrait: ${versus}`,
        caption: this.caption(result.scene),
        stem: `${this.stem(result.scene)}-trajectory-${x}-${y}`,
        csv: () => xyCSV(result.runs, 'observables', x, y),
      }),
    });
  }
}

/** A labelled select. */
export function picker(className, text) {
  const label = el('label', 'dyn-pick');
  const select = el('select', className);
  label.append(el('span', '', text), select);
  return { label, select };
}

/** Refills a select with `names`, choosing `value` (the first name when it is not there). */
export function fill(select, names, value) {
  select.replaceChildren(...names.map((n) => option(n, n)));
  select.value = names.includes(value) ? value : names[0] ?? '';
}
