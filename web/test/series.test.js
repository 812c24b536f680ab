import assert from 'node:assert/strict';
import { test } from 'node:test';
import { FLOOR, clampFloor, displaySeries, runningMean } from '../src/data/series.js';

test('running mean of a constant is the constant', () => {
  const t = [1, 2, 3, 4, 5];
  assert.deepEqual(runningMean(t, [2, 2, 2, 2, 2], 3), [2, 2, 2, 2, 2]);
});

test('running mean is the time average over the trailing window', () => {
  // Buckets (0,1]=0, (1,2]=3, (2,3]=6, (3,4]=9; window 2.
  const out = runningMean([1, 2, 3, 4], [0, 3, 6, 9], 2);
  assert.deepEqual(out, [0, 1.5, 4.5, 7.5]);
});

test('a window cutting a bucket weighs its overlap', () => {
  // Window 1.5 at t=3 covers (1.5,3]: half of bucket 2 (value 3) and bucket 3 (value 6).
  const out = runningMean([1, 2, 3], [0, 3, 6], 1.5);
  assert.equal(out[2], (3 * 0.5 + 6 * 1) / 1.5);
});

test('uneven buckets are weighted by their duration', () => {
  const out = runningMean([1, 4], [10, 1], 100);
  assert.equal(out[1], (10 * 1 + 1 * 3) / 4);
});

test('a bucket wider than the window gives its own value', () => {
  assert.deepEqual(runningMean([10, 20], [1, 5], 3), [1, 5]);
});

test('a missing value poisons the windows that contain it, not the others', () => {
  const out = runningMean([1, 2, 3, 4, 5], [1, null, 1, 1, 1], 1.5);
  assert.deepEqual(out, [1, null, null, 1, 1]);
});

test('no window: values pass, non-finite become gaps', () => {
  assert.deepEqual(runningMean([1, 2], [3, NaN], 0), [3, null]);
});

test('exact zeros and round-off are lifted to the floor, and say so', () => {
  const { values, clamped } = clampFloor([0, 1e-20, 1e-3, null]);
  assert.deepEqual(values, [FLOOR, FLOOR, 1e-3, null]);
  assert.equal(clamped, true);
  assert.equal(clampFloor([1e-10]).clamped, false);
});

test('displaySeries picks the statistic and smooths it', () => {
  const s = { t: [1, 2], mean: [1, 3], max: [2, 6] };
  assert.deepEqual(displaySeries(s, { stat: 'max' }).y, [2, 6]);
  assert.deepEqual(displaySeries(s, { stat: 'mean', window: 2 }).y, [1, 2]);
  assert.equal(displaySeries({ t: [1], mean: [0], max: [0] }).clamped, true);
});
