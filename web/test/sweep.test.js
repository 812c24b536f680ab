import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { defaultState } from '../src/data/state.js';
import {
  axisPaths,
  cellAtXY,
  cellCount,
  cellXY,
  checkAxis,
  decodeSettings,
  defaultSettings,
  expandAxis,
  gridPosition,
  gridShape,
  mapPresets,
  mapQuery,
  presetSetup,
  sweepBody,
} from '../src/map/sweep.js';

// GET /systems as the server answers it, and the Map view's presets.
const catalog = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));
const presets = JSON.parse(readFileSync(new URL('../src/map/presets.json', import.meta.url), 'utf8'));

const close = (a, b) => a.length === b.length && a.every((x, i) => Math.abs(x - b[i]) <= 1e-12 * Math.max(1, Math.abs(b[i])));

test('axes expand as the server expands them, both ends included', () => {
  assert.ok(close(expandAxis({ kind: 'linspace', numbers: [0, 0.5, 11] }), [0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5]));
  const alpha = expandAxis({ kind: 'linspace', numbers: [0.3, 0.7, 21] });
  assert.equal(alpha.length, 21);
  assert.equal(alpha[0], 0.3);
  assert.equal(alpha[20], 0.7, 'the stop is exact, not start + 20·Δ');
  assert.ok(close(expandAxis({ kind: 'logspace', numbers: [0.01, 1, 3] }), [0.01, 0.1, 1]));
  assert.ok(close(expandAxis({ kind: 'logspace', numbers: [1, 1000, 4] }), [1, 10, 100, 1000]));
  assert.deepEqual(expandAxis({ kind: 'linspace', numbers: [2, 5, 1] }), [2]);
  assert.deepEqual(expandAxis({ kind: 'values', numbers: [0.3, 0.1, 0.2] }), [0.3, 0.1, 0.2], 'values keep their order');
  // What cannot be expanded yet: no preview, no count.
  for (const bad of [
    { kind: 'linspace', numbers: [0, 1] },
    { kind: 'linspace', numbers: [0, 1, 2.5] },
    { kind: 'linspace', numbers: [0, 1, 0] },
    { kind: 'logspace', numbers: [0, 1, 5] },
    { kind: 'values', numbers: [] },
    { kind: 'values', numbers: [1, NaN] },
  ]) {
    assert.equal(expandAxis(bad), null, JSON.stringify(bad));
  }
  assert.equal(cellCount([{ kind: 'linspace', numbers: [0.3, 0.7, 21] }, { kind: 'linspace', numbers: [0, 0.5, 11] }]), 231);
  assert.equal(cellCount([{ kind: 'linspace', numbers: [0, 1] }]), null);
});

test('axis mistakes are named by the paths the server uses', () => {
  assert.deepEqual(checkAxis({ path: 'step', kind: 'logspace', numbers: [0.01, 1, 12] }, 0), []);
  assert.deepEqual(checkAxis({ path: ' ', kind: 'linspace', numbers: [0, 1, 3] }, 1).map((e) => e.path), ['axes[1].path']);
  assert.deepEqual(checkAxis({ path: 'step', kind: 'logspace', numbers: [0, 1, 3] }, 0).map((e) => e.path), ['axes[0].logspace']);
  assert.match(checkAxis({ path: 'step', kind: 'logspace', numbers: [0, 1, 3] }, 0)[0].message, /> 0/);
  assert.deepEqual(checkAxis({ path: 'q[0]', kind: 'values', numbers: [] }, 0).map((e) => e.path), ['axes[0].values']);
  assert.deepEqual(checkAxis({ path: 'q[0]', kind: 'linspace', numbers: [0, 1, 2.5] }, 0).map((e) => e.path), ['axes[0].linspace']);
});

test('a cell sits where the row-major order puts it: the last axis along x, the first along y', () => {
  const counts = [21, 11];
  assert.deepEqual(gridShape(counts), { nx: 11, ny: 21 });
  assert.deepEqual(gridPosition(0, counts), [0, 0]);
  assert.deepEqual(gridPosition(12, counts), [1, 1]);
  assert.deepEqual(gridPosition(230, counts), [20, 10]);
  assert.deepEqual(cellXY(12, counts), { x: 1, y: 1 });
  assert.deepEqual(cellXY(10, counts), { x: 10, y: 0 });
  for (let c = 0; c < 231; c++) {
    const { x, y } = cellXY(c, counts);
    assert.equal(cellAtXY(x, y, counts), c);
  }
  // Three axes: cell = (i0·n1 + i1)·n2 + i2.
  assert.deepEqual(gridPosition((2 * 3 + 1) * 4 + 3, [5, 3, 4]), [2, 1, 3]);
  // One axis: a single row.
  assert.deepEqual(gridShape([7]), { nx: 7, ny: 1 });
  assert.deepEqual(cellXY(5, [7]), { x: 5, y: 0 });
  assert.equal(cellAtXY(5, 0, [7]), 5);
});

test('the map settings round-trip through the URL beside the form state', () => {
  const state = defaultState(catalog, 'cvt_pendulum', 'rotating-perturbed');
  state.t_end = 300;
  const settings = {
    axes: [
      { path: 'methods[0].alpha', kind: 'linspace', numbers: [0.3, 0.7, 21] },
      { path: 'params.epsilon', kind: 'values', numbers: [0, 0.1, 0.25] },
    ],
    method: 2,
    integral: 'latitude',
    color: 'log',
    run: false,
  };
  const query = mapQuery(state, catalog, settings, true);
  assert.equal(
    query,
    'view=map&system=cvt_pendulum&preset=rotating-perturbed&t_end=300' +
      '&map.axis=methods[0].alpha:linspace:0.3,0.7,21&map.axis=params.epsilon:values:0,0.1,0.25' +
      '&map.method=2&map.integral=latitude&map.color=log&run=1',
  );
  const back = decodeSettings(query);
  assert.deepEqual(back.warnings, []);
  assert.deepEqual(back.settings, { ...settings, run: true });
  // The defaults are left out of the link, and come back from it.
  assert.equal(mapQuery(state, catalog, defaultSettings()), 'view=map&system=cvt_pendulum&preset=rotating-perturbed&t_end=300');
  assert.deepEqual(decodeSettings('view=map').settings, defaultSettings());
});

test('a link with an axis the map cannot use says so', () => {
  const { settings, warnings } = decodeSettings('map.axis=step:spaced:1,2&map.axis=step:values:1,2&map.axis=t_end:values:1&map.axis=q[0]:values:0&map.color=rainbow&map.method=-1');
  assert.deepEqual(settings.axes, [{ path: 'step', kind: 'values', numbers: [1, 2] }, { path: 't_end', kind: 'values', numbers: [1] }]);
  assert.equal(warnings.length, 2, warnings.join('; '));
  assert.match(warnings[0], /step:spaced/);
  assert.match(warnings[1], /at most 2 axes/);
  assert.equal(settings.color, 'verdict');
  assert.equal(settings.method, 0);
});

test('the request is the form scene with its methods, integrals and the axes', () => {
  const state = defaultState(catalog, 'knife_edge', 'paper-perturbed');
  state.integrals = ['energy'];
  const body = sweepBody(state, { axes: [{ path: ' step ', kind: 'logspace', numbers: [0.01, 1, 12] }, { path: 'params.epsilon', kind: 'linspace', numbers: [0, 0.5, 6] }] });
  assert.equal(body.system, 'knife_edge');
  assert.equal(body.preset, 'paper-perturbed');
  assert.deepEqual(body.integrals, ['energy']);
  assert.equal(body.methods.length, 5);
  assert.equal(body.points, 1000);
  assert.deepEqual(body.axes, [{ path: 'step', logspace: [0.01, 1, 12] }, { path: 'params.epsilon', linspace: [0, 0.5, 6] }]);
});

test('an axis may set the parameters, step, final time, initial state and method parameters', () => {
  const state = defaultState(catalog, 'anharmonic_cvt', 'rotating');
  state.methods = [{ id: 'dla', params: { alpha: 0.5 } }, { id: 'dd', params: {} }];
  assert.deepEqual(axisPaths(state, catalog), [
    'params.epsilon', 'params.kappa', 'step', 't_end', 'methods.alpha', 'methods[0].alpha',
    'q[0]', 'q[1]', 'q[2]', 'v[0]', 'v[1]', 'v[2]',
  ]);
  const custom = { ...state, system: { name: 's', passenger: ['x', 'y'], driver: 'z', parameters: { k: 1 }, constraints: [['1', 'z']] } };
  assert.deepEqual(axisPaths(custom, catalog).slice(0, 3), ['params.k', 'step', 't_end']);
  // A preset with more coordinates than the system's defaults (the chaotic oscillator's n = 2).
  const n2 = defaultState(catalog, 'chaotic_oscillator', 'n2');
  assert.deepEqual(axisPaths(n2, catalog).filter((p) => p.startsWith('q[')), ['q[0]', 'q[1]', 'q[2]', 'q[3]', 'q[4]']);
});

test('every preset resolves against the catalog and sets the scene and axes it names', () => {
  const usable = mapPresets(presets, catalog);
  assert.deepEqual(usable.map((p) => p.id), presets.map((p) => p.id), 'no preset names an id the catalog lacks');
  assert.ok(usable.length >= 3);
  const [alpha, knife] = usable.map((p) => presetSetup(p, catalog));
  assert.equal(alpha.state.system, 'cvt_pendulum');
  assert.equal(alpha.state.preset, 'rotating-perturbed');
  assert.equal(alpha.state.t_end, 300);
  assert.deepEqual(alpha.state.methods, [{ id: 'dla', params: { alpha: 0.5 } }]);
  assert.deepEqual(alpha.settings.axes.map((a) => [a.path, a.kind, expandAxis(a).length]), [['methods.alpha', 'linspace', 21], ['params.epsilon', 'linspace', 11]]);
  assert.deepEqual([alpha.settings.integral, alpha.settings.color, alpha.settings.run], ['energy', 'verdict', true]);
  assert.equal(knife.state.system, 'knife_edge');
  assert.equal(knife.state.methods.length, 5, "the paper's five methods");
  assert.deepEqual(knife.settings.axes.map((a) => a.path), ['step', 'params.epsilon']);
  // Each preset's body passes the server's axis checks as the page makes them.
  for (const p of usable) {
    const { state, settings } = presetSetup(p, catalog);
    assert.deepEqual(settings.axes.flatMap((a, i) => checkAxis(a, i)), [], p.id);
    assert.equal(sweepBody(state, settings).axes.length, p.axes.length, p.id);
  }
  // A preset naming what the catalog lacks is left out, not shown broken.
  const broken = [
    { ...presets[0], scene: { ...presets[0].scene, system: 'nope' } },
    { ...presets[0], scene: { ...presets[0].scene, preset: 'nope' } },
    { ...presets[0], scene: { ...presets[0].scene, methods: [{ id: 'dla', beta: 1 }] } },
    // A method that does not apply to the system (outside the paper's class).
    { ...presets[0], scene: { ...presets[0].scene, system: 'chaplygin_sleigh', preset: undefined, methods: [{ id: 'dd_avf' }] } },
    { ...presets[0], scene: { ...presets[0].scene, integrals: ['momentum'] } },
  ];
  assert.deepEqual(mapPresets(broken, catalog), []);
});
