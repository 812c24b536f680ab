import assert from 'node:assert/strict';
import { test } from 'node:test';
import { decodeState, defaultState, encodeState, requestBody } from '../src/data/state.js';

const catalog = {
  systems: [
    {
      id: 'knife_edge',
      dof: 3,
      params: [{ name: 'epsilon', default: 0, min: -1, max: 1 }],
      integrals: ['energy', 'passenger_energy', 'driver_energy', 'constraint'],
      presets: [
        { id: 'paper', label: 'Paper: ε = 0', params: { epsilon: 0 }, q: [0, 0, 1.5707963267948966], v: [0, 0, 1], step: 0.3141592653589793, t_end: 100 },
        { id: 'paper-perturbed', label: 'Paper: ε = 0.1', params: { epsilon: 0.1 }, q: [0, 0, 1.5707963267948966], v: [0, 0, 1], step: 0.3141592653589793, t_end: 100 },
      ],
    },
    { id: 'cvt_pendulum', dof: 3, params: [{ name: 'epsilon', default: 0, min: -10, max: 10 }], integrals: ['energy', 'latitude'], presets: [{ id: 'rotating', params: { epsilon: 0 }, q: [1, 1, 0], v: [0, 0, 2.8], step: 0.1, t_end: 3000 }] },
  ],
  methods: [
    { id: 'dla', params: [{ name: 'alpha', default: 0.5 }] },
    { id: 'dla01', params: [] },
    { id: 'leapfrog', params: [] },
    { id: 'dd', params: [] },
  ],
  // As GET /systems sends them: parameter values inline, with the label.
  default_methods: [
    { id: 'dla', alpha: 0.5, label: 'DLA^0.5' },
    { id: 'dla', alpha: 0.4, label: 'DLA^0.4' },
    { id: 'dla01', label: 'DLA^{0,1}' },
    { id: 'leapfrog', label: 'LF' },
    { id: 'dd', label: 'DD' },
  ],
  paper_scenes: [{ system: 'knife_edge', preset: 'paper' }, { system: 'knife_edge', preset: 'paper-perturbed' }, { system: 'cvt_pendulum', preset: 'rotating' }],
};

test('a preset with defaults encodes to a short link', () => {
  const s = defaultState(catalog, 'knife_edge', 'paper-perturbed');
  assert.equal(encodeState(s, catalog), 'system=knife_edge&preset=paper-perturbed');
  assert.equal(s.params.epsilon, 0.1);
  assert.equal(s.window, 3);
  assert.equal(defaultState(catalog, 'cvt_pendulum').window, 30);
  assert.deepEqual(s.methods.map((m) => m.id), ['dla', 'dla', 'dla01', 'leapfrog', 'dd']);
});

test('every field survives the round trip through the URL', () => {
  const s = defaultState(catalog, 'knife_edge', 'paper');
  Object.assign(s, {
    params: { epsilon: 0.25 },
    q: [0, 1e-3, 1.5],
    v: [0, 0, -1],
    step: 0.01,
    t_end: 1e4,
    points: 200,
    methods: [{ id: 'dla', params: { alpha: 0.3 } }, { id: 'dla', params: { alpha: 0.5 } }, { id: 'dd', params: {} }],
    integrals: ['energy', 'constraint'],
    stat: 'max',
    smooth: true,
    window: 7.5,
    run: true,
  });
  const query = encodeState(s, catalog);
  assert.match(query, /methods=dla:0.3,dla:0.5,dd/);
  const { state, warnings } = decodeState(query, catalog);
  assert.deepEqual(warnings, []);
  assert.deepEqual(state, s);
});

test('unknown names in a link are reported, not silently used', () => {
  const { state, warnings } = decodeState('system=nope&methods=dla:0.4,rk4', catalog);
  assert.equal(state.system, 'knife_edge');
  assert.deepEqual(state.methods, [{ id: 'dla', params: { alpha: 0.4 } }]);
  assert.equal(warnings.length, 2);
});

test('the request body uses the API names', () => {
  const s = defaultState(catalog, 'knife_edge', 'paper');
  const body = requestBody(s);
  assert.deepEqual(body.methods.slice(0, 2), [{ id: 'dla', alpha: 0.5 }, { id: 'dla', alpha: 0.4 }]);
  assert.equal(body.system, 'knife_edge');
  assert.equal(body.preset, 'paper');
  assert.equal(body.points, 1000);
});

test('the default methods are the catalog ones, with their parameters', () => {
  const s = defaultState(catalog, 'knife_edge', 'paper');
  assert.deepEqual(s.methods, [
    { id: 'dla', params: { alpha: 0.5 } },
    { id: 'dla', params: { alpha: 0.4 } },
    { id: 'dla01', params: {} },
    { id: 'leapfrog', params: {} },
    { id: 'dd', params: {} },
  ]);
  // Each state gets its own copies.
  s.methods[0].params.alpha = 0.1;
  assert.equal(defaultState(catalog, 'knife_edge', 'paper').methods[0].params.alpha, 0.5);
  // A catalog without default_methods starts from every method with its defaults.
  const bare = { ...catalog, default_methods: undefined };
  assert.deepEqual(defaultState(bare, 'knife_edge').methods.map((m) => m.id), ['dla', 'dla01', 'leapfrog', 'dd']);
});

test('links written by the page before still decode to the same state', () => {
  // The paper's link: the default methods and the paper's window (3 for the knife edge).
  const { state, warnings } = decodeState('system=knife_edge&preset=paper-perturbed&smooth=1&run=1', catalog);
  assert.deepEqual(warnings, []);
  assert.equal(state.window, 3);
  assert.equal(state.smooth, true);
  assert.equal(state.run, true);
  assert.equal(state.params.epsilon, 0.1);
  assert.deepEqual(state.methods.map((m) => [m.id, m.params.alpha]), [['dla', 0.5], ['dla', 0.4], ['dla01', undefined], ['leapfrog', undefined], ['dd', undefined]]);
  assert.equal(decodeState('system=cvt_pendulum&preset=rotating&smooth=1', catalog).state.window, 30);
  // The methods written out in full are the defaults: they re-encode to the short link.
  const full = decodeState('system=knife_edge&preset=paper&methods=dla:0.5,dla:0.4,dla01,leapfrog,dd', catalog).state;
  assert.equal(encodeState(full, catalog), 'system=knife_edge&preset=paper');
  // An explicit window still wins.
  assert.equal(decodeState('system=knife_edge&preset=paper&smooth=1&window=7', catalog).state.window, 7);
});

test('a composition travels in the link and the request body', () => {
  const composable = catalog.methods.map((m) => ({ ...m, composable: true }));
  const withCompositions = { ...catalog, methods: composable, compositions: [{ id: 'p4s3', order: 4, stages: 3 }] };
  const s = defaultState(withCompositions, 'knife_edge', 'paper');
  s.methods = [{ id: 'leapfrog', params: {}, composition: 'p4s3' }, { id: 'dla', params: { alpha: 0.5 }, composition: 'p4s3' }, { id: 'dd', params: {} }];
  const query = encodeState(s, withCompositions);
  assert.match(query, /methods=leapfrog@p4s3,dla:0.5@p4s3,dd/);
  const back = decodeState(query, withCompositions);
  assert.deepEqual(back.state.methods, s.methods);
  assert.deepEqual(requestBody(back.state).methods, [
    { id: 'leapfrog', composition: 'p4s3' },
    { id: 'dla', alpha: 0.5, composition: 'p4s3' },
    { id: 'dd' },
  ]);
  const { state, warnings } = decodeState('system=knife_edge&methods=leapfrog@p9s99', withCompositions);
  assert.deepEqual(state.methods, [{ id: 'leapfrog', params: {} }]);
  assert.match(warnings.join(' '), /unknown composition "p9s99"/);
  // A method that is not symmetric takes none (RK4 in the real catalog).
  const notComposable = { ...withCompositions, methods: [...composable, { id: 'rk4', params: [] }] };
  const other = decodeState('system=knife_edge&methods=rk4@p4s3', notComposable);
  assert.deepEqual(other.state.methods, [{ id: 'rk4', params: {} }]);
  assert.match(other.warnings.join(' '), /rk4 takes no composition/);
});

test('an empty Step field survives the URL as empty, not as 0', async () => {
  const { readFileSync } = await import('node:fs');
  const { decodeState: decode, defaultState: initial, encodeState: encode } = await import('../src/data/state.js');
  const catalog = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));
  const state = initial(catalog, 'knife_edge', 'paper');
  state.step = null;
  const query = encode(state, catalog);
  assert.match(query, /(^|&)step=(&|$)/);
  assert.equal(decode(query, catalog).state.step, null);
});

test('a PRK method travels in the link with its tableau and constraint, and goes in the request', async () => {
  const { readFileSync } = await import('node:fs');
  const real = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));
  const s = defaultState(real, 'knife_edge', 'paper');
  s.methods = [
    { id: 'prk', params: {}, tableau: 'gauss3', constraint: 'stage' },
    { id: 'prk', params: {}, tableau: 'gauss2', constraint: 'midpoint', composition: 'p4s3' },
    { id: 'prk', params: {}, tableau: 'lobatto3', constraint: 'stage', composition: 'p6s9' },
    { id: 'dla', params: { alpha: 0.5 } },
  ];
  const query = encodeState(s, real);
  // The tableau after the id, the constraint where it is not `stage`.
  assert.match(query, /methods=prk:gauss3,prk:gauss2:midpoint@p4s3,prk:lobatto3@p6s9,dla:0.5(&|$)/);
  const back = decodeState(query, real);
  assert.deepEqual(back.warnings, []);
  assert.deepEqual(back.state.methods, s.methods);
  assert.equal(encodeState(back.state, real), query);
  assert.deepEqual(requestBody(back.state, real).methods, [
    { id: 'prk', tableau: 'gauss3', constraint: 'stage' },
    { id: 'prk', tableau: 'gauss2', constraint: 'midpoint', composition: 'p4s3' },
    { id: 'prk', tableau: 'lobatto3', constraint: 'stage', composition: 'p6s9' },
    { id: 'dla', alpha: 0.5 },
  ]);
  // A bare id is the server's default, gauss2 with stage.
  assert.deepEqual(decodeState('system=knife_edge&methods=prk', real).state.methods, [{ id: 'prk', params: {}, tableau: 'gauss2', constraint: 'stage' }]);
});

test("a link's unknown tableau, refused constraint or composition of a step that is not symmetric falls back with a warning", async () => {
  const { readFileSync } = await import('node:fs');
  const real = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));
  const unknown = decodeState('system=knife_edge&methods=prk:gauss9:midpoint', real);
  assert.deepEqual(unknown.state.methods, [{ id: 'prk', params: {}, tableau: 'gauss2', constraint: 'midpoint' }]);
  assert.match(unknown.warnings.join(' '), /unknown tableau "gauss9" in the link; gauss2 instead/);
  const constraint = decodeState('system=knife_edge&methods=prk:radau2:somewhere', real);
  assert.deepEqual(constraint.state.methods, [{ id: 'prk', params: {}, tableau: 'radau2', constraint: 'stage' }]);
  assert.match(constraint.warnings.join(' '), /radau2 takes no constraint "somewhere"; stage instead/);
  // Gauss with stage conditions is not symmetric: its composition is left out.
  const composed = decodeState('system=knife_edge&methods=prk:gauss3@p4s3', real);
  assert.deepEqual(composed.state.methods, [{ id: 'prk', params: {}, tableau: 'gauss3', constraint: 'stage' }]);
  assert.match(composed.warnings.join(' '), /PRK\[gauss3\] is not symmetric, so it takes no composition; "p4s3" left out/);
});
