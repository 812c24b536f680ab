import assert from 'node:assert/strict';
import { test } from 'node:test';
import { DIVERGED, clipRange, compactTick, extent, unionExtent } from '../src/draw/axes.js';

test('time ticks stay short on a long axis', () => {
  assert.deepEqual([0, 5e5, 1e6, 1.5e6, 2e6, 3e6].map(compactTick), ['0', '5e5', '1e6', '1.5e6', '2e6', '3e6']);
  assert.deepEqual([1, 2.5, 100, 3000, 99999].map(compactTick), ['1', '2.5', '100', '3000', '99999']);
  assert.deepEqual([1e-4, 2.5e-5, -2e6].map(compactTick), ['1e−4', '2.5e−5', '−2e6']);
  assert.equal(compactTick(0.1 + 0.2), '0.3', 'no float noise');
  assert.equal(compactTick(null), '');
  // No label longer than 6 characters on the axis of a 3e6 run.
  for (let t = 0; t <= 3e6; t += 2.5e5) assert.ok(compactTick(t).length <= 6, compactTick(t));
});

test('extents keep positive finite values only', () => {
  assert.deepEqual(extent([0, null, 1e-3, NaN, 2, Infinity]), [1e-3, 2]);
  assert.equal(extent([0, null]), null);
  assert.deepEqual(unionExtent([null, [1, 2], [0.5, 1.5]]), [0.5, 2]);
  assert.equal(unionExtent([null]), null);
});

test('a diverged run is left out of the y-range, and named', () => {
  const calm = [1e-10, 1e-8, 1e-6];
  const drift = [1e-5, 1e-3, 1e-1];
  const blown = [1e-6, 1e40, 1e186];
  const r = clipRange([calm, blown, drift]);
  assert.deepEqual(r.range, [1e-10, 1e-1]);
  // A diverging run is drawn until it leaves the plot: its values below the limit count.
  assert.deepEqual(clipRange([calm, [1e-3, 1e5, 1e12, 1e186]]).range, [1e-10, 1e5]);
  assert.deepEqual(r.full, [1e-10, 1e186]);
  assert.deepEqual(r.clipped, [{ index: 1, max: 1e186 }]);
  // Nothing to clip when no run diverges, or when every run does.
  assert.deepEqual(clipRange([calm, drift]).clipped, []);
  assert.deepEqual(clipRange([blown, [1, 1e20]]), { range: [1e-6, 1e186], full: [1e-6, 1e186], clipped: [] });
  // Up to the limit a large error is data, not divergence.
  assert.deepEqual(clipRange([calm, [1, DIVERGED]]).clipped, []);
  assert.deepEqual(clipRange([]), { range: null, full: null, clipped: [] });
});

test('log axes: whole decades, the floor kept visible, powers of ten as labels', async () => {
  const { decades, logRange, power } = await import('../src/draw/axes.js');
  const near = (a, b) => a.length === b.length && a.every((x, i) => Math.abs(x / b[i] - 1) < 1e-12);
  assert.ok(near(logRange(2e-5, 3e-2, false), [1e-5, 1e-1]));
  assert.ok(near(logRange(1e-16, 1e-3, true), [1e-17, 1e-3]), 'a decade under the floor line');
  assert.ok(near(logRange(null, 1, false), [1e-17, 1]));
  assert.ok(near(decades(1e-6, 1, 300), [1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1]));
  assert.ok(decades(1e-300, 1e300, 300).length <= 12, 'thinned on a tall range');
  assert.deepEqual([1e-12, 1, 10, 1e5].map(power), ['10⁻¹²', '1', '10', '10⁵']);
});
