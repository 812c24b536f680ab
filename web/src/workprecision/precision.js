// Work–precision data, pure: the view's settings read and checked (the number of step
// sizes, or an explicit list of steps, and the repeats), the request body of
// `POST /work-precision` for the form's state, the view's URL, and the answer's rows grouped
// into one curve per method with its fitted order (the least-squares slope of log error
// against log h). Only rows that ran and have a positive, finite error become points: log
// axes cannot show 0, and a failed run is reported as failed, never drawn as a point.

import { encodeState, esc, parseList, requestBody } from '../data/state.js';

/** Default halvings and repetitions (the server's defaults too). */
export const DEFAULT_LEVELS = 4;
export const DEFAULT_REPEATS = 3;
export const MAX_LEVELS = 12;
export const MAX_REPEATS = 10;

/** The time plot's orientations: run time on x (the default), or error on x and time on y
 *  as DiffEqDevTools draws it (`orient=error-x` in the URL). */
export const ORIENTS = ['time-x', 'error-x'];

/**
 * The settings as typed (`{levels, repeats, steps}` strings) checked against the scene's
 * final time: `{settings: {levels, repeats, steps}, errors: [{field, message}]}`. A list of
 * steps, when given, replaces the number of step sizes; every entry must lie in (0, t_end].
 */
export function readSettings(raw, tEnd) {
  const errors = [];
  const whole = (field, text, max, what) => {
    const t = String(text ?? '').trim();
    const v = Number(t);
    if (t === '') errors.push({ field, message: `empty: enter ${what}, a whole number from 1 to ${max}` });
    else if (!Number.isInteger(v) || v < 1 || v > max) {
      errors.push({ field, message: `must be a whole number from 1 to ${max}${v === 0 ? ' (0 would measure nothing)' : ''}` });
    } else return v;
    return null;
  };
  const stepsText = String(raw.steps ?? '').trim();
  let steps = null;
  if (stepsText !== '') {
    steps = parseList(stepsText);
    const bad = steps.find((h) => !Number.isFinite(h));
    if (bad !== undefined) errors.push({ field: 'steps', message: 'comma-separated numbers, please' });
    else if (steps.some((h) => h <= 0)) errors.push({ field: 'steps', message: `every step h must be positive (h = ${steps.find((h) => h <= 0)} never reaches the final time)` });
    else if (Number.isFinite(tEnd) && steps.some((h) => h > tEnd)) errors.push({ field: 'steps', message: `every step h must be at most the final time ${tEnd}` });
    else if (steps.length > MAX_LEVELS) errors.push({ field: 'steps', message: `at most ${MAX_LEVELS} steps; got ${steps.length}` });
  }
  const levels = steps ? null : whole('levels', raw.levels, MAX_LEVELS, 'the number of step sizes');
  const repeats = whole('repeats', raw.repeats, MAX_REPEATS, 'the number of repeats');
  return { settings: { levels: levels ?? DEFAULT_LEVELS, repeats: repeats ?? DEFAULT_REPEATS, steps }, errors };
}

/** The body of `POST /work-precision`: the form's scene and methods (as `requestBody` writes
 *  them with the `catalog`), and either the list of `steps` or `levels` halvings of the
 *  scene's step. */
export function workPrecisionBody(state, { levels = DEFAULT_LEVELS, repeats = DEFAULT_REPEATS, steps = null } = {}, catalog) {
  const body = requestBody(state, catalog);
  delete body.points;
  if (steps?.length) body.steps = steps;
  else body.levels = levels;
  body.repeats = repeats;
  return body;
}

/** The view's query string (without `?`): the form's state, then the settings that are not
 *  the defaults. */
export function workPrecisionQuery(state, catalog, { levels = DEFAULT_LEVELS, repeats = DEFAULT_REPEATS, steps = null, orient = ORIENTS[0] } = {}) {
  // A setting may be shown as typed (a value that did not pass), so each is encoded.
  const parts = ['view=work-precision', encodeState({ ...state, run: false }, catalog)];
  if (steps?.length) parts.push(`steps=${esc(steps.join(','))}`);
  else if (String(levels) !== String(DEFAULT_LEVELS)) parts.push(`levels=${esc(levels)}`);
  if (String(repeats) !== String(DEFAULT_REPEATS)) parts.push(`repeats=${esc(repeats)}`);
  if (orient !== ORIENTS[0]) parts.push(`orient=${esc(orient)}`);
  return parts.join('&');
}

/** The settings a query string holds, as the inputs show them (strings, unchecked: a bad
 *  value is shown and reported at its field, not replaced), and the orientation. */
export function decodeSettings(query) {
  const p = new URLSearchParams(query);
  return {
    levels: p.get('levels') ?? String(DEFAULT_LEVELS),
    repeats: p.get('repeats') ?? String(DEFAULT_REPEATS),
    steps: p.get('steps') ?? '',
    orient: ORIENTS.includes(p.get('orient')) ? p.get('orient') : ORIENTS[0],
  };
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

/** Points sorted by x with equal x values moved apart by a few parts in 10¹², invisible on a
 *  log axis: uPlot.join keeps one point per x of a series, and two step sizes can end at
 *  the same error (or take the same time). */
export function distinctX(points) {
  const out = [];
  for (const [x, y] of points) {
    const prev = out.length ? out[out.length - 1][0] : null;
    out.push([prev !== null && x <= prev ? prev * (1 + 4e-12) : x, y]);
  }
  return out;
}

/** A fitted order for a table or legend: two decimals, or "–" when there is none. */
export function formatOrder(order) {
  return order === null || order === undefined ? '–' : order.toFixed(2);
}
