// A run's verdict on one integral as a small badge beside its curve's legend entry: the word
// (exact, bounded, drift), so it reads without colour, in the verdict's colour, with the
// numbers behind it on hover; "…" while the run goes on, "–" when it has none.

import { runVerdicts } from '../data/verdicts.js';

/** Puts (or updates) the verdict badge of `run` on `integral` in a uPlot legend row. */
export function legendVerdict(row, run, integral) {
  const [v] = runVerdicts(run, [integral]);
  let badge = row.querySelector('.legend-verdict');
  if (!badge) {
    badge = document.createElement('span');
    badge.className = 'legend-verdict';
    (row.querySelector('.u-label') ?? row).after(badge);
  }
  if (badge.dataset.kind === v.kind && badge.title === v.title) return;
  badge.className = `legend-verdict ${v.kind}`;
  badge.dataset.kind = v.kind;
  badge.textContent = v.label;
  badge.title = v.title;
}
