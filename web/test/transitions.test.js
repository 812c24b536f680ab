import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { defaultWindow } from '../src/data/catalog.js';
import { isCustom } from '../src/data/custom.js';
import { defaultState } from '../src/data/state.js';
import { customized, experiment, presetSwitched, sceneOpened, startedFrom, systemSwitched } from '../src/explore/transitions.js';

const catalog = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));
const methods = [{ id: 'leapfrog', params: {} }, { id: 'dla', params: { alpha: 0.4 } }];

test('a new system takes its first preset; the methods and display stay', () => {
  const current = { ...defaultState(catalog, 'knife_edge', 'paper'), methods, stat: 'max', smooth: true };
  const next = systemSwitched(catalog, current, 'cvt_pendulum');
  assert.equal(next.system, 'cvt_pendulum');
  assert.equal(next.preset, 'oscillating');
  assert.deepEqual(next.methods, methods);
  assert.equal(next.stat, 'max');
  assert.equal(next.smooth, true);
  assert.ok(next.methods.length && systemSwitched(catalog, { ...current, methods: [] }, 'cvt').methods.length, 'no methods: the defaults');
});

test('a new preset refills its values; the window follows the final time only while it is the default', () => {
  const current = { ...defaultState(catalog, 'cvt_pendulum', 'oscillating'), methods, preset: 'rotating' };
  const next = presetSwitched(catalog, current);
  const rotating = defaultState(catalog, 'cvt_pendulum', 'rotating');
  for (const k of ['params', 'q', 'v', 'step', 't_end']) assert.deepEqual(next[k], rotating[k], k);
  assert.deepEqual(next.methods, methods);
  assert.equal(next.window, rotating.window, 'the default window follows the new final time');
  const own = presetSwitched(catalog, { ...current, window: 7 });
  assert.equal(own.window, 7, 'a window of the user’s own stays');
});

test('the editor opens on the system shown, as formulas with its values and state', () => {
  const current = { ...defaultState(catalog, 'knife_edge', 'paper-perturbed'), methods, q: [1, 2, 3], integrals: ['energy', 'latitude'] };
  const next = customized(catalog, current);
  assert.ok(isCustom(next.system));
  assert.deepEqual(next.q, [1, 2, 3]);
  assert.deepEqual(next.methods, methods);
  assert.ok(next.integrals.includes('energy'));
  assert.equal(next.system.parameters.epsilon, current.params.epsilon, 'the parameters at their values');
  const started = startedFrom(catalog, current, 'cvt');
  assert.deepEqual(started.q, defaultState(catalog, 'cvt').q, 'Start from: the built-in’s initial state');
  assert.deepEqual(started.methods, methods);
});

test('an experiment and an opened scene run what they name, the rest from the preset', () => {
  const x = experiment(catalog, { system: 'knife_edge', preset: 'paper', integrals: ['energy'] });
  assert.deepEqual([x.system, x.preset, x.integrals, x.smooth], ['knife_edge', 'paper', ['energy'], true]);
  const scene = { system: 'cvt_pendulum', preset: 'rotating', params: { epsilon: 0.3 }, t_end: 500, integrals: ['latitude'] };
  const opened = sceneOpened(catalog, scene, [{ id: 'dla', alpha: 0.45, label: 'DLA^0.45' }, { id: 'leapfrog', composition: 'p4s3' }]);
  const preset = defaultState(catalog, 'cvt_pendulum', 'rotating');
  assert.equal(opened.params.epsilon, 0.3);
  assert.deepEqual(opened.q, preset.q);
  assert.equal(opened.t_end, 500);
  assert.equal(opened.window, defaultWindow(500));
  assert.deepEqual(opened.methods, [{ id: 'dla', params: { alpha: 0.45 } }, { id: 'leapfrog', params: {}, composition: 'p4s3' }]);
});

test("a map cell's PRK method opens with its tableau and constraint, not as parameters", () => {
  const scene = { system: 'knife_edge', preset: 'paper' };
  const opened = sceneOpened(catalog, scene, [{ id: 'prk', tableau: 'gauss2', constraint: 'midpoint', composition: 'p4s3', label: 'PRK[gauss2, midpoint]∘p4s3' }]);
  assert.deepEqual(opened.methods, [{ id: 'prk', params: {}, tableau: 'gauss2', constraint: 'midpoint', composition: 'p4s3' }]);
});
