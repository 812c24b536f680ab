// Work–precision data, pure: the request body of `POST /work-precision` for the form's
// state, the view's URL, and the answer's rows grouped into one curve per method with its
// fitted order (the least-squares slope of log error against log h). Only rows that ran and
// have a positive, finite error become points: log axes cannot show 0, and a failed run is
// reported as failed, never drawn as a point.

import { encodeState, requestBody } from './state.js';

/** Default halvings and repetitions (the server's defaults too). */
export const DEFAULT_LEVELS = 4;
export const DEFAULT_REPEATS = 3;
export const MAX_LEVELS = 12;
export const MAX_REPEATS = 10;

/** The body of `POST /work-precision`: the form's scene and methods, `levels` halvings. */
export function workPrecisionBody(state, { levels = DEFAULT_LEVELS, repeats = DEFAULT_REPEATS } = {}) {
  const body = requestBody(state);
  delete body.points;
  body.levels = levels;
  body.repeats = repeats;
  return body;
}

/** The view's query string (without `?`): the form's state, then levels and repeats when not the defaults. */
export function workPrecisionQuery(state, catalog, { levels = DEFAULT_LEVELS, repeats = DEFAULT_REPEATS } = {}) {
  const parts = ['view=work-precision', encodeState({ ...state, run: false }, catalog)];
  if (levels !== DEFAULT_LEVELS) parts.push(`levels=${levels}`);
  if (repeats !== DEFAULT_REPEATS) parts.push(`repeats=${repeats}`);
  return parts.join('&');
}

/** `levels` and `repeats` from a query string, clamped to what the server takes. */
export function decodeSettings(query) {
  const p = new URLSearchParams(query);
  const int = (name, fallback, max) => {
    const v = Number(p.get(name));
    return p.has(name) && Number.isInteger(v) ? Math.min(Math.max(v, 1), max) : fallback;
  };
  return { levels: int('levels', DEFAULT_LEVELS, MAX_LEVELS), repeats: int('repeats', DEFAULT_REPEATS, MAX_REPEATS) };
}

/**
 * The least-squares slope of log10(y) against log10(x) over the points with x, y positive
 * and finite; null with fewer than two such points or when every x is the same.
 */
export function fitSlope(points) {
  const usable = points.filter(([x, y]) => x > 0 && y > 0 && Number.isFinite(x) && Number.isFinite(y));
  if (usable.length < 2) return null;
  const xs = usable.map(([x]) => Math.log10(x));
  const ys = usable.map(([, y]) => Math.log10(y));
  const mx = xs.reduce((a, b) => a + b, 0) / xs.length;
  const my = ys.reduce((a, b) => a + b, 0) / ys.length;
  let sxy = 0;
  let sxx = 0;
  xs.forEach((x, i) => {
    sxy += (x - mx) * (ys[i] - my);
    sxx += (x - mx) ** 2;
  });
  return sxx > 0 ? sxy / sxx : null;
}

/** Whether a row is a drawable point: it ran to t_end with a positive, finite error. */
export function plottable(row) {
  return row.status === 'ok' && row.final_error > 0 && Number.isFinite(row.final_error);
}

/**
 * One curve per method (in the answer's order): its rows, the points of error against run
 * time and against h (each sorted by x), the fitted order and the failed rows.
 */
export function curves(response) {
  const byLabel = new Map();
  for (const row of response.rows ?? []) {
    const label = row.method?.label ?? row.method?.id ?? '?';
    if (!byLabel.has(label)) byLabel.set(label, { label, method: row.method, rows: [] });
    byLabel.get(label).rows.push(row);
  }
  return [...byLabel.values()].map((c) => {
    const ok = c.rows.filter(plottable);
    const byX = (a, b) => a[0] - b[0];
    const time = ok.filter((r) => r.elapsed_ms > 0).map((r) => [r.elapsed_ms, r.final_error]).sort(byX);
    const step = ok.map((r) => [r.step, r.final_error]).sort(byX);
    return {
      ...c,
      time,
      step,
      order: fitSlope(step),
      failed: c.rows.filter((r) => r.status !== 'ok'),
    };
  });
}

/** A fitted order for a table or legend: two decimals, or "–" when there is none. */
export function formatOrder(order) {
  return order === null || order === undefined ? '–' : order.toFixed(2);
}
