// The Paper view: Modin & Verdier's figures side by side, computed live — the knife edge's
// energy error (ε = 0 and 0.1) and the pendulum-driven CVT's passenger energy, driver energy
// and latitude (oscillating and rotating driver, ε = 0 and 0.5) — with the paper's running
// means (3 time units for the knife edge, 30 for the CVT), each figure with its caption and,
// under each panel, the scorecard row that summarises it: the verdict of each method.
//
// The six scenes are streamed one after another (the server admits a few simulations at once;
// a 503 is retried after its Retry-After), each feeding the panels that show it.

import { retrying, simulate } from './api.js';
import { Plots } from './plots.js';
import { Result } from './result.js';
import { PAPER_METHODS, requestBody } from './state.js';
import { VERDICTS, verdictTitle } from './verdicts.js';

const KNIFE = [
  { system: 'knife_edge', preset: 'paper', title: 'ε = 0' },
  { system: 'knife_edge', preset: 'paper-perturbed', title: 'ε = 0.1' },
];
const CVT = [
  { system: 'cvt_pendulum', preset: 'oscillating', title: 'oscillating driver, ε = 0' },
  { system: 'cvt_pendulum', preset: 'rotating', title: 'rotating driver, ε = 0' },
  { system: 'cvt_pendulum', preset: 'oscillating-perturbed', title: 'oscillating driver, ε = 0.5' },
  { system: 'cvt_pendulum', preset: 'rotating-perturbed', title: 'rotating driver, ε = 0.5' },
];

/** The paper's figures: what each shows, its running-mean window and its caption. */
export const FIGURES = [
  {
    id: 'knife-energy',
    title: 'Knife edge: energy error |H − H(0)|',
    integral: 'energy',
    window: 3,
    panels: KNIFE,
    caption:
      'ε = 0: the reversible methods (DLA^0.5, DLA^{0,1}, LF) keep the energy error bounded; DLA^0.4, not reversible, drifts; DD conserves the energy exactly. ε = 0.1 (a perturbation that breaks reversibility): every method drifts except DD, which conserves energy by construction.',
  },
  {
    id: 'cvt-passenger',
    title: 'CVT: passenger energy error |E − E(0)|',
    integral: 'passenger_energy',
    window: 30,
    panels: CVT,
    caption:
      'The reversible methods keep the passenger energy nearly conserved while the driver stays reversible; DLA^0.4 drifts. With the rotating driver and ε = 0.5 (bottom right) the energy drifts systematically for every method but LF.',
  },
  {
    id: 'cvt-driver',
    title: 'CVT: driver energy error |h − h(0)|',
    integral: 'driver_energy',
    window: 30,
    panels: CVT,
    caption:
      'Only DD fails to nearly conserve the driver energy (its discrete gradient couples the driver to the passenger). Even DLA^0.4 behaves well: the driver is a Hamiltonian system of its own and DLA^0.4 is symplectic on it.',
  },
  {
    id: 'cvt-latitude',
    title: 'CVT: latitude error |ℓ − ℓ(0)| (hidden integral, at the section crossings)',
    integral: 'latitude',
    window: 30,
    panels: CVT,
    caption:
      'Reversible KAM theory explains the near conservation for reversible methods: with the oscillating driver, or with ε = 0, every reversible method keeps the latitude bounded. With the rotating driver and ε = 0.5 every method fails except LF — an open problem of the paper.',
  },
];

/** The scenes to stream: each paper scene once, with the integrals its panels show. */
export function paperScenes() {
  const scenes = new Map();
  for (const f of FIGURES) {
    for (const p of f.panels) {
      const key = `${p.system}/${p.preset}`;
      if (!scenes.has(key)) scenes.set(key, { system: p.system, preset: p.preset, integrals: [] });
      const s = scenes.get(key);
      if (!s.integrals.includes(f.integral)) s.integrals.push(f.integral);
    }
  }
  return [...scenes.values()];
}

export class PaperView {
  constructor(root) {
    this.root = root;
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
    const figures = FIGURES.map((f) => {
      const fig = el('figure', 'paper-figure');
      fig.dataset.figure = f.id;
      fig.append(el('h3', 'figure-title', f.title));
      const grid = el('div', `panel-grid n${f.panels.length}`);
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
        this.panels.push({ key: panel.dataset.scene, integral: f.integral, window: f.window, plots: new Plots(plotBox), summary });
      }
      const caption = el('figcaption', 'figure-caption');
      caption.append(el('strong', '', 'The paper: '), f.caption, ` Running mean over ${f.window} time units; step and span as in the paper.`);
      fig.append(grid, caption);
      return fig;
    });
    this.figures.replaceChildren(...figures);
  }

  async load() {
    this.controller?.abort();
    const mine = new AbortController();
    this.controller = mine;
    this.done = false;
    this.#build();
    const scenes = paperScenes();
    try {
      for (const [i, scene] of scenes.entries()) {
        this.#status('running', `Computing scene ${i + 1} of ${scenes.length}: ${scene.system}/${scene.preset}…`);
        await this.#stream(scene, mine);
        if (this.controller !== mine) return;
      }
      this.done = true;
      this.#status('done', `Done: ${scenes.length} scenes, ${this.panels.length} panels, ${PAPER_METHODS.length} methods each.`);
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
      methods: PAPER_METHODS,
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
      (wait) => this.#status('running', `The server is busy; retrying ${key} in ${wait} s…`),
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
      chip.append(el('span', 'chip-label', run.label), el('span', 'chip-kind', VERDICTS.find((x) => x.kind === kind)?.label ?? (kind === 'pending' ? '…' : run.status)));
      chip.title = run.status === 'failed' ? `${run.label}: failed: ${run.error}` : verdictTitle(v, `${run.label}: `);
      return chip;
    });
    panel.summary.replaceChildren(...chips);
  }

  #status(state, text) {
    this.status.dataset.state = state;
    this.status.textContent = text;
  }
}

function el(tag, className, text) {
  const e = document.createElement(tag);
  if (className) e.className = className;
  if (text !== undefined) e.textContent = text;
  return e;
}
