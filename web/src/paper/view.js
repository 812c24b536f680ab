// The Paper view: Modin & Verdier's figures side by side, computed live. Everything about
// systems and methods comes from the /systems catalog (catalog.js): the scenes are its
// `paper_scenes`, the methods its `default_methods`; each system of the scenes gets a figure
// per integral its paper figures show (its total energy, or its split energies and hidden
// integral) with a panel per scene, smoothed with the preset's default running mean; each
// figure has a note on what the paper finds and, under each panel, the scorecard row that
// summarises it: the verdict of each method. The panels of a figure share one y-range, so
// the scenes compare side by side as in the paper; each names its scene.
//
// After them, one figure the paper does not have (section.js): Poincaré sections of the
// rotating perturbed CVT by two methods beside the reference's.
//
// The scenes are streamed one after another (the server admits a few simulations at once;
// a 503 is retried after its Retry-After), each feeding the panels that show it.

import { retrying, simulate } from '../data/api.js';
import { defaultMethods, figureScenes, paperFigures } from '../data/catalog.js';
import { Plots } from '../draw/plots.js';
import { Result } from '../data/result.js';
import { requestBody } from '../data/state.js';
import { VERDICTS, verdictTitle } from '../data/verdicts.js';
import { el } from '../draw/dom.js';
import { sceneCaption, sceneStem } from '../data/custom.js';
import { humanLabel } from '../data/labels.js';
import { PaperSection } from './section.js';

/** What the paper finds about each integral's error, in terms of the methods' properties. */
export const PAPER_NOTES = {
  energy:
    'Without perturbation (ε = 0) the reversible methods keep the energy error bounded, a method that is not reversible drifts, and one that conserves the energy by construction keeps it exact. A perturbation that breaks reversibility (ε ≠ 0) makes every method drift except those that conserve the energy by construction.',
  passenger_energy:
    'The reversible methods keep the passenger energy nearly conserved while the driver stays reversible; a method that is not reversible drifts. With a rotating, perturbed driver the energy drifts systematically for all of the paper’s methods but one.',
  driver_energy:
    'A method whose discrete gradient couples the driver to the passenger fails to nearly conserve the driver energy. The driver is a Hamiltonian system of its own: a method symplectic on it keeps its energy nearly conserved, even when the method is not reversible.',
  latitude:
    'Reversible KAM theory explains the near conservation by reversible methods: with an oscillating driver, or without perturbation, every reversible method keeps the latitude bounded. With a rotating, perturbed driver all of the paper’s methods but one fail — an open problem of the paper.',
};

/** The figures of the view, each with its caption's note. */
export function figures(catalog) {
  return paperFigures(catalog).map((f) => ({ ...f, note: PAPER_NOTES[f.integral] ?? '' }));
}


export class PaperView {
  constructor(root, { catalog }) {
    this.root = root;
    this.catalog = catalog;
    this.figureList = figures(catalog);
    this.methods = defaultMethods(catalog);
    this.status = root.querySelector('.view-status');
    this.figures = root.querySelector('.paper-figures');
    this.panels = []; // {key, integral, window, plots, summary}
    this.controller = null;
    this.done = false;
    root.querySelector('.paper-run').addEventListener('click', () => this.load());
  }

  /** Computes the figures once (again on the button). */
  show() {
    if (!this.done && !this.controller) this.load();
  }

  #build() {
    for (const p of this.panels) p.plots.destroy();
    this.panels = [];
    const nodes = this.figureList.map((f) => {
      const fig = el('figure', 'paper-figure');
      fig.dataset.figure = f.id;
      fig.append(el('h3', 'figure-title', f.title));
      const grid = el('div', `panel-grid n${f.panels.length}`);
      // One y-range for the figure's panels.
      const group = { extents: new Map() };
      for (const p of f.panels) {
        const panel = el('section', 'paper-panel');
        panel.dataset.scene = `${p.system}/${p.preset}`;
        panel.dataset.integral = f.integral;
        panel.append(el('h4', 'panel-title', p.title));
        const plotBox = el('div', 'panel-plot');
        const summary = el('div', 'verdict-row');
        summary.append(el('span', 'pending', 'verdicts: waiting for the runs…'));
        panel.append(plotBox, summary);
        grid.append(panel);
        const plots = new Plots(plotBox, {
          group,
          catalog: this.catalog,
          label: (run) => humanLabel(run.label),
          caption: (scene) => sceneCaption(scene, this.catalog),
          stem: (scene) => sceneStem(scene, this.catalog),
        });
        this.panels.push({ key: panel.dataset.scene, integral: f.integral, window: p.window, plots, summary, group });
      }
      const caption = el('figcaption', 'figure-caption');
      if (f.note) caption.append(el('strong', '', 'The paper: '), `${f.note} `);
      const windows = [...new Set(f.panels.map((p) => p.window))].join(' or ');
      caption.append(`Running mean over ${windows} time units; step and span as in the paper; the panels share one y-range.`);
      fig.append(grid, caption);
      return fig;
    });
    this.figures.replaceChildren(...nodes);
    this.section = new PaperSection(this.figures, { catalog: this.catalog });
  }

  async load() {
    this.controller?.abort();
    const mine = new AbortController();
    this.controller = mine;
    this.done = false;
    this.#build();
    const scenes = figureScenes(this.figureList);
    try {
      for (const [i, scene] of scenes.entries()) {
        this.#status('running', `Computing scene ${i + 1} of ${scenes.length}: ${sceneCaption(scene, this.catalog)}…`);
        await this.#stream(scene, mine);
        if (this.controller !== mine) return;
      }
      this.#status('running', 'Computing the Poincaré sections of the rotating perturbed CVT…');
      await this.section.load(mine.signal, (wait) => this.#status('running', `The server is busy; retrying the sections in ${wait} s…`));
      if (this.controller !== mine) return;
      this.done = true;
      this.#status('done', `Done: ${scenes.length} scenes, ${this.panels.length} panels, ${this.methods.length} methods each, and the sections.`);
    } catch (e) {
      if (this.controller !== mine || e.name === 'AbortError') return;
      this.#status('error', `The paper's figures failed: ${e.message}`);
    } finally {
      if (this.controller === mine) this.controller = null;
    }
  }

  async #stream(scene, mine) {
    const key = `${scene.system}/${scene.preset}`;
    const panels = this.panels.filter((p) => p.key === key);
    const body = requestBody({
      system: scene.system,
      preset: scene.preset,
      params: {},
      q: [],
      v: [],
      step: null,
      t_end: null,
      methods: this.methods,
      integrals: scene.integrals,
      points: 1000,
    });
    let result = null;
    let frame = 0;
    const draw = () => {
      frame = 0;
      for (const p of panels) p.plots.update({ stat: 'mean', window: p.window });
    };
    await retrying(
      () =>
        simulate(body, {
          signal: mine.signal,
          onEvent: (name, data) => {
            if (this.controller !== mine) return;
            if (name === 'scene') {
              result = new Result(data);
              // Each panel plots one integral of the scene's result (same runs, shared).
              for (const p of panels) p.plots.reset({ scene: { ...data, integrals: [p.integral] }, runs: result.runs });
            } else if (name === 'points') result?.addPoints(data);
            else if (name === 'progress') result?.progress(data);
            else if (name === 'run') {
              result?.finishRun(data);
              for (const p of panels) this.#summary(p, result);
            }
            if (!frame) frame = requestAnimationFrame(draw);
          },
        }),
      (wait) => this.#status('running', `The server is busy; retrying ${sceneCaption(scene, this.catalog)} in ${wait} s…`),
      mine.signal,
    );
    cancelAnimationFrame(frame);
    draw();
  }

  // The scorecard row of a panel: each method's verdict on the panel's integral.
  #summary(panel, result) {
    const chips = result.runs.map((run) => {
      const v = run.verdicts?.[panel.integral];
      const kind = run.status === 'running' ? 'pending' : v?.kind ?? 'none';
      const chip = el('span', `verdict-chip ${kind}`);
      chip.dataset.kind = kind;
      const label = humanLabel(run.label);
      chip.append(el('span', 'chip-label', label), el('span', 'chip-kind', VERDICTS.find((x) => x.kind === kind)?.label ?? (kind === 'pending' ? '…' : run.status)));
      chip.title = run.status === 'failed' ? `${label}: failed: ${run.error}` : verdictTitle(v, `${label}: `);
      return chip;
    });
    panel.summary.replaceChildren(...chips);
  }

  #status(state, text) {
    this.status.dataset.state = state;
    this.status.textContent = text;
  }
}
