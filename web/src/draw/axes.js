// Axis helpers of the plots: compact tick labels for a long time axis (3e6 as "3e6", not
// "3,000,000"), whole-decade ranges and ticks written as powers of ten on the log error
// axis, and the y-range of a log plot over the runs that did not diverge, so one run blowing
// up to 1e186 does not flatten every other curve (the plot says which runs leave it). Pure
// functions, so node tests cover them.

import { FLOOR } from '../data/series.js';
import { superscript } from '../data/labels.js';

/** An error above this, with another run staying below it, marks a run as off the scale. */
export const DIVERGED = 1e8;

/** A tick label: plain for moderate values, `2.5e6` / `1e−4` for large and tiny ones. */
export function compactTick(v) {
  if (v === null || v === undefined || !Number.isFinite(v)) return '';
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (a >= 1e5 || a < 1e-3) {
    const [m, e] = v.toExponential(3).split('e');
    return `${Number(m)}e${Number(e)}`.replace('-', '−');
  }
  return String(Number(v.toPrecision(6)));
}

/** The positive, finite extent `[min, max]` of some values; null when there are none. */
export function extent(values) {
  let min = Infinity;
  let max = -Infinity;
  for (const v of values ?? []) {
    if (typeof v !== 'number' || !(v > 0) || !Number.isFinite(v)) continue;
    if (v < min) min = v;
    if (v > max) max = v;
  }
  return max >= min ? [min, max] : null;
}

/**
 * The y-range of a log plot of several runs (`runs`: arrays of y values): when some run stays
 * at or below `limit` and another goes above it, the extent of every value at or below the
 * limit (a diverging run is drawn until it leaves the plot); the runs above it are `clipped`
 * (their indices, with their largest value). `full` is the extent of all.
 */
export function clipRange(runs, limit = DIVERGED) {
  const extents = runs.map(extent);
  const full = unionExtent(extents);
  const kept = extents.filter((e) => e && e[1] <= limit);
  if (!kept.length || kept.length === extents.filter(Boolean).length) return { range: full, full, clipped: [] };
  const clipped = [];
  const below = [...kept];
  extents.forEach((e, i) => {
    if (!e || e[1] <= limit) return;
    clipped.push({ index: i, max: e[1] });
    below.push(extent(runs[i].filter((v) => v <= limit)));
  });
  return { range: unionExtent(below), full, clipped };
}

/** The union of several extents (nulls ignored); null when all are null. */
export function unionExtent(list) {
  let out = null;
  for (const e of list) {
    if (!e) continue;
    out = out ? [Math.min(out[0], e[0]), Math.max(out[1], e[1])] : [e[0], e[1]];
  }
  return out;
}

// Whole decades around the data, one decade below the floor when the floor is in use so its
// line stays visible above the axis.
export function logRange(min, max, clamped) {
  if (!(min > 0) || !(max > 0)) return [FLOOR / 10, 1];
  let lo = 10 ** Math.floor(Math.log10(min) + 1e-9);
  let hi = 10 ** Math.ceil(Math.log10(max) - 1e-9);
  if (clamped || min <= FLOOR) lo = Math.min(lo, FLOOR / 10);
  if (hi <= lo) hi = lo * 10;
  return [lo, hi];
}

// Ticks at whole decades only, thinned so labels stay ~28 px apart on a tall range.
export function decades(min, max, height) {
  const lo = Math.ceil(Math.log10(min) - 1e-9);
  const hi = Math.floor(Math.log10(max) + 1e-9);
  const stride = Math.max(1, Math.ceil((28 * (hi - lo + 1)) / Math.max(height, 1)));
  const out = [];
  // Multiples of the stride, so 1 = 10⁰ is always a tick when in range.
  for (let e = Math.floor(hi / stride) * stride; e >= lo; e -= stride) out.unshift(10 ** e);
  return out;
}

/** 10 to the integer power `k`, the exponent in superscript: 10⁻¹². */
export function powerOfTen(k) {
  return `10${superscript(k)}`;
}

// 1e-12 → "10⁻¹²"; 1 and 10 as themselves.
export function power(v) {
  const e = Math.round(Math.log10(v));
  if (e === 0) return '1';
  if (e === 1) return '10';
  return powerOfTen(e);
}
