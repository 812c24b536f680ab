import assert from 'node:assert/strict';
import { test } from 'node:test';
import { curves, decodeSettings, fitSlope, formatOrder, plottable, workPrecisionBody, workPrecisionQuery } from '../src/precision.js';
import { defaultState } from '../src/state.js';

const catalog = {
  systems: [
    {
      id: 'knife_edge',
      dof: 3,
      params: [{ name: 'epsilon', default: 0, min: -1, max: 1 }],
      integrals: ['energy', 'constraint'],
      presets: [{ id: 'paper', label: 'Paper: ε = 0', params: { epsilon: 0 }, q: [0, 0, 1.5707963267948966], v: [0, 0, 1], step: 0.3141592653589793, t_end: 100 }],
    },
  ],
  methods: [{ id: 'leapfrog', params: [] }, { id: 'dd', params: [] }],
};

test('the slope of an exact power law is its exponent', () => {
  const h = [0.1, 0.05, 0.025, 0.0125];
  assert.ok(Math.abs(fitSlope(h.map((x) => [x, 3 * x ** 2])) - 2) < 1e-12);
  assert.ok(Math.abs(fitSlope(h.map((x) => [x, 0.5 * x ** 4])) - 4) < 1e-12);
  // Noise: the least-squares fit, not the first and last point alone.
  const noisy = [[1, 1], [2, 4.4], [4, 15], [8, 66]];
  const s = fitSlope(noisy);
  assert.ok(s > 1.9 && s < 2.1, `${s}`);
});

test('the slope ignores points a log axis cannot show and needs two distinct x', () => {
  assert.equal(fitSlope([]), null);
  assert.equal(fitSlope([[0.1, 1e-3]]), null);
  assert.equal(fitSlope([[0.1, 1e-3], [0.1, 2e-3]]), null);
  assert.equal(fitSlope([[0.1, 1e-3], [0.05, 0], [0.02, NaN], [-1, 1]]), null);
  assert.ok(Math.abs(fitSlope([[0.1, 1e-2], [0.05, 0], [0.01, 1e-4]]) - 2) < 1e-12);
});

const row = (label, step, final_error, elapsed_ms, status = 'ok') => ({
  method: { id: label.toLowerCase(), label },
  step,
  steps: Math.round(10 / step),
  elapsed_ms,
  final_error,
  max_error: {},
  status,
  error: status === 'ok' ? null : 'step 3 at t = 2: diverged',
});

test('rows group into one curve per method with its order; failed rows are never points', () => {
  const response = {
    rows: [
      row('LF', 0.1, 4e-3, 0.2),
      row('LF', 0.05, 1e-3, 0.4),
      row('LF', 0.025, 2.5e-4, 0.8),
      row('DD', 0.1, null, 0.01, 'failed'),
      row('DD', 0.05, 2e-3, 0.5),
      row('DD', 0.025, 0, 1.0),
    ],
  };
  const [lf, dd] = curves(response);
  assert.equal(lf.label, 'LF');
  assert.ok(Math.abs(lf.order - 2) < 1e-12);
  assert.deepEqual(lf.step, [[0.025, 2.5e-4], [0.05, 1e-3], [0.1, 4e-3]], 'sorted by h');
  assert.deepEqual(lf.time, [[0.2, 4e-3], [0.4, 1e-3], [0.8, 2.5e-4]], 'sorted by time');
  assert.equal(lf.failed.length, 0);
  assert.equal(dd.failed.length, 1);
  assert.deepEqual(dd.step, [[0.05, 2e-3]], 'neither the failed row nor the zero error is a point');
  assert.equal(dd.order, null);
  assert.equal(formatOrder(dd.order), '–');
  assert.equal(formatOrder(lf.order), '2.00');
  assert.equal(plottable(row('X', 0.1, 1e-3, 1, 'failed')), false);
});

test('the request is the form scene without points, with levels and repeats', () => {
  const state = defaultState(catalog, 'knife_edge', 'paper');
  state.t_end = 10;
  const body = workPrecisionBody(state, { levels: 5, repeats: 2 });
  assert.equal(body.system, 'knife_edge');
  assert.equal(body.t_end, 10);
  assert.equal(body.points, undefined);
  assert.deepEqual([body.levels, body.repeats], [5, 2]);
  assert.deepEqual(body.methods, [{ id: 'leapfrog' }, { id: 'dd' }]);
});

test('the view and its settings round-trip through the URL', () => {
  const state = defaultState(catalog, 'knife_edge', 'paper');
  state.t_end = 10;
  const q = workPrecisionQuery(state, catalog, { levels: 6, repeats: 3 });
  assert.equal(q, 'view=work-precision&system=knife_edge&preset=paper&t_end=10&levels=6');
  assert.deepEqual(decodeSettings(q), { levels: 6, repeats: 3 });
  assert.deepEqual(decodeSettings('levels=99&repeats=0'), { levels: 12, repeats: 1 });
  assert.deepEqual(decodeSettings('levels=x'), { levels: 4, repeats: 3 });
});
