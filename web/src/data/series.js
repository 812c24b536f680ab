// What the plots show of an error series: the chosen per-bucket statistic, optionally smoothed
// by the paper's running mean, with values below the floor lifted to it. A log axis cannot
// show 0, and an energy-conserving method's energy error is 0 or round-off: such points sit
// on a marked floor line instead of spiking to the bottom of the axis. Pure functions, so
// node tests cover them.

/** Errors below this are shown at it (exact within round-off). */
export const FLOOR = 1e-16;

/**
 * Trailing running mean over `window` time units of a piecewise-constant series: bucket k
 * holds the value y[k] over (t[k-1], t[k]] (the first bucket starts at `t0`). The mean at t[k]
 * is the time average over (t[k] - window, t[k]] (over (t0, t[k]] while t[k] - window < t0).
 * A bucket wider than the window gives its own value. Missing values (null or NaN) poison
 * every window that contains them: a diverged run must not look smooth.
 */
export function runningMean(t, y, window, t0 = 0) {
  const n = Math.min(t.length, y.length);
  const out = new Array(n);
  if (!(window > 0)) {
    for (let k = 0; k < n; k++) out[k] = finite(y[k]) ? y[k] : null;
    return out;
  }
  // prefix[k] = integral of the series over (t0, t[k-1]]; bad[k] = missing values in buckets < k.
  const prefix = new Float64Array(n + 1);
  const bad = new Int32Array(n + 1);
  for (let k = 0; k < n; k++) {
    const start = k === 0 ? t0 : t[k - 1];
    const ok = finite(y[k]);
    prefix[k + 1] = prefix[k] + (ok ? y[k] * Math.max(0, t[k] - start) : 0);
    bad[k + 1] = bad[k] + (ok ? 0 : 1);
  }
  let j = 0; // first bucket whose end lies inside the window
  for (let k = 0; k < n; k++) {
    const left = Math.max(t0, t[k] - window);
    while (j < k && t[j] <= left) j++;
    // Buckets j..k overlap the window; bucket j only from `left` on.
    if (bad[k + 1] - bad[j] > 0) {
      out[k] = null;
      continue;
    }
    const startJ = j === 0 ? t0 : t[j - 1];
    const width = t[k] - left;
    if (!(width > 0)) {
      out[k] = y[k];
      continue;
    }
    const whole = prefix[k + 1] - prefix[j + 1]; // buckets j+1..k
    const partial = y[j] * (t[j] - Math.max(left, startJ));
    out[k] = (whole + partial) / width;
  }
  return out;
}

/** Lifts values below `floor` to it; reports whether any was lifted. */
export function clampFloor(y, floor = FLOOR) {
  let clamped = false;
  const values = y.map((v) => {
    if (v === null || !Number.isFinite(v)) return null;
    if (v < floor) {
      clamped = true;
      return floor;
    }
    return v;
  });
  return { values, clamped };
}

/**
 * The curve to draw for one bucketed series `{t, mean, max}`.
 * Options: `stat` ("mean" | "max"), `window` (running-mean window, 0 or absent: none).
 */
export function displaySeries(series, { stat = 'mean', window = 0 } = {}) {
  const raw = stat === 'max' ? series.max : series.mean;
  const smoothed = window > 0 ? runningMean(series.t, raw, window) : raw.map((v) => (finite(v) ? v : null));
  const { values, clamped } = clampFloor(smoothed);
  return { t: series.t, y: values, clamped };
}

function finite(v) {
  return typeof v === 'number' && Number.isFinite(v);
}
