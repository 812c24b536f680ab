// Text alternatives of the plots, which are canvases: a sentence per plot naming what it
// shows and, per curve, its last value and its verdict (or its status), for the canvas's
// aria-label and a visually hidden summary beside it. Pure functions, so node tests cover
// them.

/** The last finite value of a series, or null. */
export function lastValue(values) {
  for (let k = (values?.length ?? 0) - 1; k >= 0; k--) {
    const v = values[k];
    if (typeof v === 'number' && Number.isFinite(v)) return v;
  }
  return null;
}

/** A number as the summary reads it: `3.10e-5`, `0`, or `no value`. */
export function sci(v) {
  if (v === null || v === undefined || !Number.isFinite(v)) return 'no value';
  return v === 0 ? '0' : v.toExponential(2);
}

/**
 * The summary of a plot: `Title (scene): A: last error 1.00e-3, bounded; B: failed.`
 * `items`: `{label, text}` per curve.
 */
export function plotSummary(title, scene, items) {
  const head = scene ? `${title} (${scene})` : title;
  if (!items.length) return `${head}: no curves.`;
  return `${head}: ${items.map((i) => `${i.label}: ${i.text}`).join('; ')}.`;
}

/** A time-series curve's summary: its last error, then its verdict or its status. */
export function curveText(values, { verdict = null, status = 'ok' } = {}) {
  const last = `last error ${sci(lastValue(values))}`;
  if (status === 'running') return `${last}, running`;
  if (status !== 'ok') return `${last}, ${status}`;
  return verdict ? `${last}, ${verdict}` : last;
}
