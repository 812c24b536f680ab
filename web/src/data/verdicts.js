// Verdicts and properties as the page shows them: the words, colours and hover texts of the
// scorecard grid and the paper view's summary rows, and the scorecard's layout (which
// integrals each scene has, the properties of a method per system). Pure functions, so node
// tests cover them.

import { humanLabel } from './labels.js';

/** The three verdicts, in the legend's order. */
export const VERDICTS = [
  { kind: 'exact', label: 'exact', letter: 'E', text: 'conserved to round-off' },
  { kind: 'bounded', label: 'bounded', letter: 'B', text: 'oscillates, no growth' },
  { kind: 'drift', label: 'drift', letter: 'D', text: 'grows with t' },
];

/** Short names of the integrals for column heads. */
export const INTEGRAL_SHORT = {
  energy: 'H',
  passenger_energy: 'E',
  driver_energy: 'h',
  latitude: 'ℓ',
  constraint: 'A q̇',
};

/** Human names of the integrals. */
export const INTEGRAL_NAME = {
  energy: 'energy',
  passenger_energy: 'passenger energy',
  driver_energy: 'driver energy',
  latitude: 'latitude',
  constraint: 'constraint residual',
};

/** A verdict's number: `1.23e-4`, or `–` for none. */
export const sci = (x) => (x === null || x === undefined ? '–' : Number(x).toExponential(2));

/** Whether a drift is one of an integral consumed (the API's rule: the error sits late at its
 *  largest and at half the integral or more), not of a late/early ratio above 1. */
export function consumed(verdict) {
  return verdict?.kind === 'drift' && Number.isFinite(verdict.ratio) && verdict.ratio <= 1;
}

/** The hover text of a verdict: the numbers behind it, and why a drift whose ratio is not
 *  above 1 is one. */
export function verdictTitle(verdict, context = '') {
  if (!verdict) return `${context}no verdict (no data)`.trim();
  const ratio = verdict.ratio === null || verdict.ratio === undefined ? '∞' : Number(verdict.ratio).toFixed(2);
  const why = consumed(verdict) ? ' — the integral is consumed: the error sits at its largest, half the integral’s size or more, to the end' : '';
  return `${context}${verdict.kind}: max ${sci(verdict.max)}, early max ${sci(verdict.early)}, late mean ${sci(verdict.late)}, late/early ${ratio}${why}`;
}

/**
 * A run's verdict per integral, as the runs table shows them: `pending` while it runs, `none`
 * where a series got no verdict (no data, or the run failed first), with the numbers behind
 * each verdict on hover.
 */
export function runVerdicts(run, integrals) {
  return integrals.map((integral) => {
    const v = run.verdicts?.[integral] ?? null;
    const kind = run.status === 'running' ? 'pending' : v?.kind ?? 'none';
    const name = INTEGRAL_NAME[integral] ?? integral;
    const who = humanLabel(run.label);
    const title = kind === 'pending' ? `${who}, ${name}: running` : verdictTitle(v, `${who}, ${name}: `);
    return { integral, short: INTEGRAL_SHORT[integral] ?? integral, kind, label: VERDICTS.find((x) => x.kind === kind)?.label ?? (kind === 'pending' ? '…' : '–'), title };
  });
}

/** The integrals of a scorecard scene, in the order the grid shows them. */
export function sceneIntegrals(scene) {
  return scene.scene.integrals ?? [];
}

/** Scene ids grouped by system, in order of first appearance: [[system, [sceneIds]]]. */
export function systemsOf(card) {
  const out = new Map();
  for (const s of card.scenes) {
    const system = s.scene.system;
    if (!out.has(system)) out.set(system, []);
    out.get(system).push(s.id);
  }
  return [...out];
}

/** The properties the scorecard shows per method and system: short column head, name, and
 *  the numbers behind a measurement. */
export const PROPERTIES = [
  { id: 'reversible', short: 'rev', name: 'reversible', numbers: (p) => `round-trip defect ${sci(p.reversibility_defect)} (≤ 1e-11 to pass)` },
  { id: 'symmetric', short: 'sym', name: 'symmetric (Φ₋ₕ ∘ Φₕ = id)', numbers: (p) => `Φ₋ₕ ∘ Φₕ defect ${sci(p.symmetry_defect)} (≤ 1e-11 to pass)` },
  {
    id: 'preserves_fibration',
    short: 'fib',
    name: 'preserves the fibration',
    numbers: (p) => `driver coupling ${sci(p.driver_coupling)}, fiber coupling ${sci(p.fiber_coupling)}, constraint defect ${sci(p.constraint_defect)} (each ≤ 1e-12 to pass)`,
  },
];

/** A property mark's sign and words: measured on every scene (yes, no), on some (mixed),
 *  failed (unknown), not defined (the fibration outside the paper's class), the method not
 *  applying to the system. */
export const MARKS = {
  yes: ['✓', 'yes'],
  no: ['✗', 'no'],
  mixed: ['±', 'mixed'],
  unknown: ['?', 'unknown (the measurement failed)'],
  not_defined: ['–', 'not defined outside the paper’s class'],
  not_applicable: ['n/a', 'not applicable: the method has no step for this system'],
};

/** Whether a scorecard run is of a method that has no step for its scene's system. */
export const notApplicable = (run) => run?.status === 'not_applicable';

/**
 * A method's property on a system, over the system's scenes: `yes` when measured true on
 * every scene, `no` when false on every one, `mixed` otherwise; `not_applicable` when the
 * method has no step for the system, `not_defined` for the fibration outside the paper's
 * class, `unknown` when no measurement succeeded; with a hover text listing the measured
 * numbers per scene.
 */
export function propertyMark(card, methodIndex, system, property) {
  const label = card.methods[methodIndex].label;
  const { name, numbers } = PROPERTIES.find((p) => p.id === property);
  const rows = card.properties.filter(
    (p, i) => p.system === system && i % card.methods.length === methodIndex && p.method.label === label,
  );
  const runOf = (p) => card.scenes.find((s) => s.id === p.scene)?.runs?.[methodIndex];
  const applying = rows.filter((p) => !notApplicable(runOf(p)));
  const values = applying.map((p) => p[property]).filter((v) => v === true || v === false);
  let mark = 'unknown';
  if (values.length && values.every((v) => v)) mark = 'yes';
  else if (values.length && values.every((v) => !v)) mark = 'no';
  else if (values.length) mark = 'mixed';
  else if (rows.length && !applying.length) mark = 'not_applicable';
  else if (property === 'preserves_fibration' && applying.length && applying.every((p) => !p.error)) mark = 'not_defined';
  const lines = rows.map((p) => {
    const run = runOf(p);
    if (notApplicable(run)) return `${p.scene}: not applicable${run.error ? ` (${run.error})` : ''}`;
    if (p.error) return `${p.scene}: ${p.error}`;
    if (p[property] === null || p[property] === undefined) return `${p.scene}: not defined outside the paper’s class`;
    return `${p.scene}: ${numbers(p)}`;
  });
  return { mark, title: [`${label} on ${system}: ${name}: ${MARKS[mark][1]}`, ...lines].join('\n') };
}
