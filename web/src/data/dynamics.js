// What the Trajectory and Section panels ask for and draw, as pure functions: the quantities
// a system offers (its coordinates and their velocities, `x1` and `x1_dot`), sensible
// default picks per system (the paper's class: the passenger plane, the section where the
// driver turns through 2πm; otherwise the first two coordinates, the section at the first
// coordinate's zero), the request's `observables` and `section` fields, a run's columns as
// x/y pairs, nice linear ticks and a padded range, and a panel's CSV. Node tests cover them.

import { csvField } from './csv.js';
import { isCustom, isGeneral } from './custom.js';
import { findSystem } from './catalog.js';

/** The API's limit on observables per request. */
export const MAX_OBSERVABLES = 16;

/** The time axis's pick in the Trajectory panel: a quantity against t. */
export const TIME = 't';

/**
 * What the panels work with for the form's system: `key` (changes when the coordinates or
 * the system do), `coords`, `quantities` (coordinates, then velocities) and `defaults`
 * `{trajectory: {x, y}, section: {surface, direction, x, y}}`.
 */
export function dynamicsSystem(catalog, system) {
  let coords = [];
  let passenger = null;
  let driver = null;
  let id = '';
  if (isCustom(system)) {
    // As custom.js `coordinateNames`, but a system being edited may lack a field.
    coords = (isGeneral(system) ? system.coordinates : [...(system.passenger ?? []), system.driver]).filter(Boolean);
    if (!isGeneral(system)) {
      passenger = system.passenger ?? [];
      driver = system.driver || null;
    }
    id = 'custom';
  } else {
    const info = findSystem(catalog, system);
    coords = [...(info?.general?.coordinates ?? [])];
    // A built-in in the paper's own form (the ζ systems): its driver is an angle.
    if (info?.formulas?.driver) {
      passenger = info.formulas.passenger ?? [];
      driver = info.formulas.driver;
    }
    id = info?.id ?? String(system);
  }
  const quantities = [...coords, ...coords.map((c) => `${c}_dot`)];
  return { key: `${id}:${coords.join(',')}`, coords, quantities, defaults: defaultPicks(coords, passenger, driver) };
}

/** The default picks: the passenger plane and the driver's turns for the paper's form; the
 *  first two coordinates, and the second's phase plane at the first's zero, otherwise. */
export function defaultPicks(coords, passenger = null, driver = null) {
  const a = coords[0] ?? 'x';
  const b = coords[1] ?? `${a}_dot`;
  if (driver && passenger?.length) {
    const p = passenger[0];
    const q = passenger[1] ?? `${p}_dot`;
    return { trajectory: { x: p, y: q }, section: { surface: `sin(${driver}/2)`, direction: 'both', x: p, y: q } };
  }
  const c = coords[1] ? `${coords[1]}_dot` : `${a}_dot`;
  return { trajectory: { x: a, y: b }, section: { surface: a, direction: 'up', x: coords[1] ?? a, y: c } };
}

/** The observables to ask for: every quantity when they fit the API's limit (so a new pick
 *  draws without running again), else only the picked ones. Bare names: the fast case. */
export function observablesFor(quantities, picked) {
  const names = quantities.length <= MAX_OBSERVABLES ? quantities : [...new Set(picked.filter((p) => p !== TIME))];
  return Object.fromEntries(names.map((n) => [n, n]));
}

/** The request's `section` field. */
export function sectionFor({ surface, direction, x, y }) {
  return { surface: String(surface).trim(), direction, plot: x === y ? [x] : [x, y] };
}

/** A run's x/y pairs for two columns of its `observables` or `section` (`part`), or null
 *  when the run has no such columns. `t` names the time column. */
export function xyColumns(run, part, x, y) {
  const cols = run?.[part];
  if (!cols || !Array.isArray(cols[x]) || !Array.isArray(cols[y])) return null;
  return { xs: cols[x], ys: cols[y] };
}

/** The smallest and largest finite values of several arrays, or null. */
export function finiteExtent(arrays) {
  let min = Infinity;
  let max = -Infinity;
  for (const a of arrays) {
    for (const v of a ?? []) {
      if (typeof v !== 'number' || !Number.isFinite(v)) continue;
      if (v < min) min = v;
      if (v > max) max = v;
    }
  }
  return max >= min ? [min, max] : null;
}

/** A range around an extent with a margin of `pad` of its width (a single value gets ±1, or
 *  ±10 % of itself). */
export function paddedRange(extent, pad = 0.04) {
  if (!extent) return [-1, 1];
  const [lo, hi] = extent;
  if (hi > lo) {
    const m = (hi - lo) * pad;
    return [lo - m, hi + m];
  }
  const d = lo === 0 ? 1 : Math.abs(lo) * 0.1;
  return [lo - d, hi + d];
}

/** About `count` round ticks (1, 2, 5 × 10ⁿ apart) inside [lo, hi]. */
export function niceTicks(lo, hi, count = 5) {
  if (!(hi > lo) || !Number.isFinite(lo) || !Number.isFinite(hi)) return [];
  const raw = (hi - lo) / Math.max(1, count);
  const p = 10 ** Math.floor(Math.log10(raw));
  // The round step nearest above two thirds of the even one: "about" count ticks.
  const step = [1, 2, 5, 10].map((k) => k * p).find((s) => s >= raw / 1.5) ?? 10 * p;
  const out = [];
  for (let k = Math.ceil(lo / step - 1e-9); k * step <= hi + step * 1e-9; k++) {
    // Rounded to the step's digits, so 0.30000000000000004 reads 0.3 and 0 is never −0.
    out.push(Number((k * step).toPrecision(12)) + 0);
  }
  return out;
}

/** A panel's CSV: one row per point, `run,method,status,<x>,<y>` (and `t` first when the
 *  columns are not against t). */
export function xyCSV(runs, part, x, y) {
  const withT = x !== TIME && y !== TIME;
  const head = ['run', 'method', 'status', ...(withT ? ['t'] : []), x, y].map(csvField).join(',');
  const rows = [head];
  runs.forEach((run, i) => {
    const cols = run[part];
    const xy = xyColumns(run, part, x, y);
    if (!xy) return;
    for (let k = 0; k < xy.xs.length; k++) {
      rows.push([i, csvField(run.label), run.status, ...(withT ? [num(cols.t?.[k])] : []), num(xy.xs[k]), num(xy.ys[k])].join(','));
    }
  });
  return rows.join('\n') + '\n';
}

function num(v) {
  return v === null || v === undefined ? '' : String(v);
}
