import assert from 'node:assert/strict';
import { test } from 'node:test';
import { ORIENTS, curves, decodeSettings, distinctX, fitSlope, formatOrder, plottable, readSettings, workPrecisionBody, workPrecisionQuery } from '../src/workprecision/precision.js';
import { defaultState } from '../src/data/state.js';

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
  assert.deepEqual(decodeSettings(q), { levels: '6', repeats: '3', steps: '', orient: 'time-x' });
  // Bad values stay as typed, to be reported at their field rather than replaced.
  assert.deepEqual(decodeSettings('levels=0&repeats=x'), { levels: '0', repeats: 'x', steps: '', orient: 'time-x' });
  // A list of steps replaces levels; the DiffEqDevTools orientation is kept.
  const q2 = workPrecisionQuery(state, catalog, { levels: 6, repeats: 2, steps: [0.1, 0.05], orient: 'error-x' });
  assert.equal(q2, 'view=work-precision&system=knife_edge&preset=paper&t_end=10&steps=0.1,0.05&repeats=2&orient=error-x');
  assert.deepEqual(decodeSettings(q2), { levels: '4', repeats: '2', steps: '0.1,0.05', orient: 'error-x' });
  assert.equal(decodeSettings('orient=sideways').orient, 'time-x');
  // A value shown as typed is encoded: it cannot add or break parameters of the URL.
  const q3 = workPrecisionQuery(state, catalog, { levels: '3&view=map', repeats: '2 #x' });
  assert.equal(new URLSearchParams(q3).get('view'), 'work-precision');
  assert.deepEqual(decodeSettings(q3), { levels: '3&view=map', repeats: '2 #x', steps: '', orient: 'time-x' });
});

test('step sizes: 0, negative, empty or too many are errors at their field, never a silent 1', () => {
  const ok = readSettings({ levels: '5', repeats: '2', steps: '' }, 100);
  assert.deepEqual(ok, { settings: { levels: 5, repeats: 2, steps: null }, errors: [] });
  for (const levels of ['0', '-2', '', '1.5', '13', 'x']) {
    const { errors } = readSettings({ levels, repeats: '3', steps: '' }, 100);
    assert.deepEqual(errors.map((e) => e.field), ['levels'], `levels = ${JSON.stringify(levels)}`);
  }
  assert.match(readSettings({ levels: '0', repeats: '3' }, 100).errors[0].message, /0 would measure nothing/);
  assert.deepEqual(readSettings({ levels: '4', repeats: '0' }, 100).errors.map((e) => e.field), ['repeats']);
  assert.deepEqual(readSettings({ levels: '4', repeats: '11' }, 100).errors.map((e) => e.field), ['repeats']);
});

test('a list of steps replaces levels; each must lie in (0, t_end]', () => {
  const { settings, errors } = readSettings({ levels: '0', repeats: '1', steps: '0.1, 0.05 0.025' }, 10);
  assert.deepEqual(errors, [], 'levels is not read when steps are given');
  assert.deepEqual(settings.steps, [0.1, 0.05, 0.025]);
  const body = workPrecisionBody(defaultState(catalog, 'knife_edge', 'paper'), settings);
  assert.deepEqual([body.steps, body.levels, body.repeats], [[0.1, 0.05, 0.025], undefined, 1]);
  const error = (steps, tEnd = 10) => readSettings({ levels: '4', repeats: '3', steps }, tEnd).errors;
  assert.match(error('0.1, 0')[0].message, /positive \(h = 0 never reaches/);
  assert.equal(error('0.1, 0')[0].field, 'steps');
  assert.match(error('-0.1')[0].message, /positive/);
  assert.match(error('0.1, abc')[0].message, /numbers/);
  assert.match(error('20')[0].message, /at most the final time 10/);
  assert.deepEqual(error('20', null), [], 'without a final time the server checks');
  assert.match(error(Array.from({ length: 13 }, (_, i) => 0.1 / (i + 1)).join(','))[0].message, /at most 12/);
});

test('the time plot can be drawn with error on x and time on y', () => {
  assert.deepEqual(ORIENTS, ['time-x', 'error-x']);
});

test('points of one curve at the same x stay two points', () => {
  const out = distinctX([[1e-3, 1], [1e-3, 2], [1e-3, 3], [2e-3, 4]]);
  assert.equal(new Set(out.map(([x]) => x)).size, 4);
  assert.deepEqual(out.map(([, y]) => y), [1, 2, 3, 4]);
  for (const [x] of out) assert.ok(Math.abs(x / 1e-3 - 1) < 1e-10 || x === 2e-3);
});
