// The Paper view's one figure the paper does not have (the catalog's `paper_section`): the
// Poincaré section of the rotating perturbed CVT where the driver completes a turn, in the
// passenger plane, by leap-frog and DLA^½ beside the reference's, drawn in grey beneath them.
// Reversible KAM theory says where the tori survive; the section shows whether each method's
// crossings stay on closed curves, as the exact ones do, or spread. The caption says what the
// run's verdicts said, once they are in. One stream, after the paper's figures.

import { simulate, retrying } from '../data/api.js';
import { el } from '../draw/dom.js';
import { Result } from '../data/result.js';
import { XYCard } from '../draw/xycard.js';
import { xyColumns, xyCSV } from '../data/dynamics.js';
import { humanLabel } from '../data/labels.js';
import { sceneCaption, sceneStem } from '../data/custom.js';
import { VERDICTS } from '../data/verdicts.js';

/** The figure's request from the catalog's `paper_section`: scene, methods (labels dropped),
 *  the section and the integrals whose verdicts the caption reports. */
export function sectionRequest(catalog, points = 200) {
  const f = catalog.paper_section;
  const methods = f.methods.map(({ label, ...m }) => m);
  return { system: f.system, preset: f.preset, methods, integrals: f.integrals, section: f.section, points };
}

/** Whether a run's method is an instrument (the reference) in the catalog. */
function instrument(catalog, run) {
  return catalog.methods.find((m) => m.id === run.method?.id)?.instrument === true;
}

/** The caption's sentence on the verdicts: per method under study, its verdict per integral. */
export function verdictSentence(catalog, runs) {
  const name = (kind) => VERDICTS.find((v) => v.kind === kind)?.label ?? kind ?? 'no verdict';
  const parts = runs
    .filter((r) => !instrument(catalog, r))
    .map((r) => {
      if (r.status === 'failed') return `${humanLabel(r.label)} failed (${r.error})`;
      const says = catalog.paper_section.integrals.map((i) => `${i.replace('_', ' ')} ${name(r.verdicts?.[i]?.kind)}`);
      return `${humanLabel(r.label)}: ${says.join(', ')}`;
    });
  return parts.length ? `The verdicts: ${parts.join('; ')}.` : '';
}

export class PaperSection {
  constructor(container, { catalog }) {
    this.catalog = catalog;
    const fig = el('figure', 'paper-figure');
    fig.dataset.figure = 'section';
    fig.append(el('h3', 'figure-title', 'Not in the paper: Poincaré sections of the rotating perturbed CVT'));
    const [x, y] = catalog.paper_section.section.plot;
    this.card = new XYCard(fig, { panel: 'paper-section', title: 'Section where the driver completes a turn', sub: `${y} against ${x}` });
    this.caption = el('figcaption', 'figure-caption');
    fig.append(this.caption);
    container.append(fig);
    this.#caption('');
  }

  #caption(verdicts) {
    this.caption.replaceChildren(
      el('strong', '', 'Beyond the paper: '),
      'each time the driver completes a turn (ζ = 2πm) the passenger’s position is marked, one cloud per method and the reference in grey beneath. Where a method keeps the invariant tori its marks lie on closed curves as the reference’s do; where it breaks them they spread. ',
      verdicts,
    );
  }

  /** Streams the figure's run (after the paper's figures), drawing as crossings come. */
  async load(signal, onBusy) {
    const body = sectionRequest(this.catalog);
    let result = null;
    let frame = 0;
    const draw = () => {
      frame = 0;
      if (!result) return;
      const [x, y] = body.section.plot;
      this.card.draw(result.runs, this.catalog, {
        columns: (run) => xyColumns(run, 'section', x, y),
        mode: 'points',
        xLabel: x,
        yLabel: y,
        empty: 'No crossing yet.',
        describe: () => ({
          title: `Poincaré section: ${y} against ${x} at ζ = 2πm`,
          caption: sceneCaption(result.scene, this.catalog),
          stem: `${sceneStem(result.scene, this.catalog)}-section`,
          csv: () => xyCSV(result.runs, 'section', x, y),
        }),
      });
    };
    await retrying(
      () =>
        simulate(body, {
          signal,
          onEvent: (name, data) => {
            if (name === 'scene') result = new Result(data);
            else if (name === 'section') result?.addSection(data);
            else if (name === 'points') result?.addPoints(data);
            else if (name === 'progress') result?.progress(data);
            else if (name === 'run') {
              result?.finishRun(data);
              this.#caption(verdictSentence(this.catalog, result.runs));
            }
            if (!frame) frame = requestAnimationFrame(draw);
          },
        }),
      onBusy,
      signal,
    );
    cancelAnimationFrame(frame);
    draw();
  }
}
