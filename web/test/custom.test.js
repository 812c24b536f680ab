import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { customFrom, customIntegrals, isCustom, sceneCaption, systemName } from '../src/data/custom.js';
import { customFromFields } from '../src/data/customfields.js';
import { workPrecisionBody } from '../src/workprecision/precision.js';
import { decodeState, defaultCustomState, defaultState, encodeState, requestBody } from '../src/data/state.js';

const catalog = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));
const [first] = catalog.systems;
const withTwoRows = catalog.systems.find((s) => s.formulas?.constraints.length === 2);

// The state the editor shows after "Start from" the first system, at its first preset.
function started(id = first.id) {
  const base = defaultState(catalog, id);
  const state = defaultCustomState(catalog, customFrom(catalog, id, base.params));
  Object.assign(state, { q: base.q, v: base.v, step: base.step, t_end: base.t_end });
  return state;
}

test('a built-in system starts the editor as its formula form, at the values shown', () => {
  const sys = customFrom(catalog, first.id, { epsilon: 0.25 });
  assert.deepEqual(sys, { ...first.formulas, parameters: { epsilon: 0.25 } });
  assert.ok(isCustom(sys));
  assert.equal(isCustom(first.id), false);
  // A copy: editing it leaves the catalog alone.
  sys.constraints[0][0] = '0';
  assert.notEqual(first.formulas.constraints[0][0], '0');
});

test('a custom system survives the round trip through the URL', () => {
  const state = started();
  const query = encodeState(state, catalog);
  assert.ok(query.startsWith('custom=Knife+edge+(skate+on+an+inclined+plane)&passenger=x1,x2&driver=zeta&param.epsilon=0&U=-x1&Vd=0&A=-sin(zeta),cos(zeta)+-+epsilon&q='), query);
  assert.ok(!query.includes('system=') && !query.includes('preset='), query);
  const { state: back, warnings } = decodeState(query, catalog);
  assert.deepEqual(warnings, []);
  assert.deepEqual(back, state);
});

test('awkward names and formulas come back exactly', () => {
  const state = started(withTwoRows.id);
  Object.assign(state, {
    system: {
      name: 'a & b = 50% #1, ε/2 + x',
      passenger: ['x,1', 'y%2C', 'φ'],
      driver: 'ζ',
      parameters: { k: 1.5, 'c 2': -3e-7, eps: 0 },
      passenger_potential: 'k*(x^2 + y^2)/2 + 1e-3*φ',
      driver_potential: '((ζ) /2) - 0.5e+1',
      constraints: [['1', '0', 'cos(ζ)'], ['0', '1', 'sin(ζ) ,']],
    },
    q: [0, 1e-3, 2, -1],
    v: [1, 0, -1, 0.5],
    step: 0.05,
    t_end: 2e4,
    integrals: ['energy', 'constraint'],
    methods: [{ id: 'leapfrog', params: {} }],
    smooth: true,
    window: 7,
    run: true,
  });
  const { state: back } = decodeState(encodeState(state, catalog), catalog);
  assert.deepEqual(back, state);
  // A parameter value that is not a number stays NaN, for the form to mark.
  state.system.parameters.k = NaN;
  assert.ok(Number.isNaN(decodeState(encodeState(state, catalog), catalog).state.system.parameters.k));
});

test('a custom link without a window takes the default for its final time', () => {
  const state = started();
  state.t_end = 3000;
  state.window = 30;
  const query = encodeState(state, catalog);
  assert.ok(!query.includes('window='), query);
  assert.equal(decodeState(query, catalog).state.window, 30);
});

test('built-in links do not change', () => {
  const s = defaultState(catalog, first.id, first.presets[1].id);
  assert.equal(encodeState(s, catalog), `system=${first.id}&preset=${first.presets[1].id}`);
  s.params.epsilon = 0.5;
  assert.equal(encodeState(s, catalog), `system=${first.id}&preset=${first.presets[1].id}&param.epsilon=0.5`);
});

test('a custom system is posted as its object, without preset and params', () => {
  const state = started();
  state.system.parameters.epsilon = 0.1;
  state.integrals = ['energy'];
  const body = requestBody(state);
  assert.deepEqual(Object.keys(body), ['system', 'q', 'v', 'step', 't_end', 'methods', 'integrals', 'points']);
  assert.deepEqual(body.system, { ...first.formulas, parameters: { epsilon: 0.1 } });
  assert.deepEqual(body.q, first.presets[0].q);
  assert.equal(body.step, first.presets[0].step);
  assert.deepEqual(body.integrals, ['energy']);
  // Empty step and final time are left to the server's defaults.
  Object.assign(state, { step: null, t_end: null });
  const bare = requestBody(state);
  assert.ok(!('step' in bare) && !('t_end' in bare));
  // Work–precision posts the same scene.
  const wp = workPrecisionBody(started());
  assert.ok(isCustom(wp.system) && !('preset' in wp) && !('params' in wp) && !('points' in wp));
});

test("the editor's inputs become the system object, or say what cannot be sent", () => {
  const fields = {
    name: 'skate in a bowl',
    passenger: ' x ,y ',
    driver: ' theta ',
    parameters: [['k', '1'], [' eps ', '0.1']],
    passenger_potential: 'k*(x^2 + y^2)/2',
    driver_potential: '0',
    constraints: [['-sin(theta)', 'cos(theta) - eps']],
  };
  const { system, invalid } = customFromFields(fields);
  assert.deepEqual(invalid, []);
  assert.deepEqual(system, {
    name: 'skate in a bowl',
    passenger: ['x', 'y'],
    driver: 'theta',
    parameters: { k: 1, eps: 0.1 },
    passenger_potential: 'k*(x^2 + y^2)/2',
    driver_potential: '0',
    constraints: [['-sin(theta)', 'cos(theta) - eps']],
  });
  const bad = customFromFields({ ...fields, parameters: [['k', 'one'], ['', '2'], ['eps', '1'], ['eps', '2'], ['m', '']] });
  assert.deepEqual(bad.invalid.map((e) => e.path), ['system.parameters.k', 'system.parameters', 'system.parameters.eps', 'system.parameters.m']);
  // Blank names stay, for the server to name by position.
  assert.deepEqual(customFromFields({ ...fields, passenger: 'x,,y' }).system.passenger, ['x', '', 'y']);
});

test('the latitude is offered only for two passengers and one constraint', () => {
  assert.ok(customIntegrals(customFrom(catalog, first.id)).includes('latitude'));
  assert.ok(!customIntegrals(customFrom(catalog, withTwoRows.id)).includes('latitude'));
  assert.ok(!defaultCustomState(catalog, customFrom(catalog, first.id)).integrals.includes('latitude'));
});

test('labels name a custom scene by its name', () => {
  const sys = customFrom(catalog, first.id, { epsilon: 0.1 });
  sys.name = 'my skate';
  assert.equal(systemName(sys, catalog), 'my skate');
  assert.equal(systemName({ ...sys, name: ' ' }, catalog), 'Custom system');
  assert.equal(systemName(first.id, catalog), first.name);
  const scene = { system: sys, preset: null, params: {}, step: 0.1, t_end: 100 };
  assert.equal(sceneCaption(scene, catalog), 'my skate (custom) · epsilon = 0.1 · h = 0.1 · t_end = 100');
  const builtin = { system: first.id, preset: first.presets[1].id, params: { epsilon: 0.1 }, step: 0.5, t_end: 100 };
  assert.equal(sceneCaption(builtin, catalog), `${first.name} · knife edge, ε = 0.1 · h = 0.5 · t_end = 100`);
  builtin.params.epsilon = 0.2;
  assert.match(sceneCaption(builtin, catalog), / · knife edge, ε = 0.1 · epsilon = 0.2 · /);
});
