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

/** The hover text of a verdict: the numbers behind it. */
export function verdictTitle(verdict, context = '') {
  if (!verdict) return `${context}no verdict (no data)`.trim();
  const ratio = verdict.ratio === null || verdict.ratio === undefined ? '∞' : Number(verdict.ratio).toFixed(2);
  return `${context}${verdict.kind}: max ${sci(verdict.max)}, early max ${sci(verdict.early)}, late mean ${sci(verdict.late)}, late/early ${ratio}`;
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

/**
 * A method's property on a system, over the system's scenes: `yes` when measured true on
 * every scene, `no` when false on every one, `mixed` otherwise, `unknown` when no measurement
 * succeeded; with a hover text listing the measured numbers per scene.
 */
export function propertyMark(card, methodIndex, system, property) {
  const label = card.methods[methodIndex].label;
  const rows = card.properties.filter(
    (p, i) => p.system === system && i % card.methods.length === methodIndex && p.method.label === label,
  );
  const values = rows.map((p) => p[property]).filter((v) => v === true || v === false);
  let mark = 'unknown';
  if (values.length && values.every((v) => v)) mark = 'yes';
  else if (values.length && values.every((v) => !v)) mark = 'no';
  else if (values.length) mark = 'mixed';
  const numbers = rows.map((p) => {
    if (p.error) return `${p.scene}: ${p.error}`;
    if (property === 'reversible') return `${p.scene}: round-trip defect ${sci(p.reversibility_defect)} (≤ 1e-11 to pass)`;
    return `${p.scene}: driver coupling ${sci(p.driver_coupling)}, fiber coupling ${sci(p.fiber_coupling)}, constraint defect ${sci(p.constraint_defect)} (each ≤ 1e-12 to pass)`;
  });
  return { mark, title: [`${label} on ${system}: ${property === 'reversible' ? 'reversible' : 'preserves the fibration'}: ${mark}`, ...numbers].join('\n') };
}
