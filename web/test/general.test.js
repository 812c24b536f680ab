import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { coordinateNames, customFrom, customIntegrals, defaultCustomIntegrals, formOf, inForm, isGeneral, massMode, startingPoints, toGeneral } from '../src/data/custom.js';
import { customFromFields } from '../src/data/customfields.js';
import { decodeCustom, encodeCustom } from '../src/data/customurl.js';
import { decodeState, defaultState, encodeState, requestBody } from '../src/data/state.js';
import { customized, presetSwitched, sceneOpened, startedFrom, systemSwitched } from '../src/explore/transitions.js';

// GET /systems as the server answers it: the paper's systems and the literature's beside them.
const catalog = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));
const find = (id) => catalog.systems.find((s) => s.id === id);
const sleigh = find('chaplygin_sleigh');
const disk = find('vertical_disk');
const ids = (methods) => methods.map((m) => m.id);

// The sleigh in the general form, as tests/tests/http/general_form.rs sends it.
const SLEIGH = {
  name: 'Chaplygin sleigh',
  coordinates: ['x', 'y', 'theta'],
  parameters: { m: 2, I: 0.5, a: 0.5, g: 0 },
  mass: [['m', 0, 0], [0, 'm', 0], [0, 0, 'I']],
  potential: 'm*g*y',
  constraints: [['-sin(theta)', 'cos(theta)', '-a']],
  invariants: { kinetic: 'm*(x_dot^2 + y_dot^2)/2 + I*theta_dot^2/2' },
  detect_class: true,
};

test('every built-in starts the editor in the general form; those of the paper’s class in its form too', () => {
  const starts = startingPoints(catalog);
  assert.deepEqual(starts.general.map((s) => s.id), catalog.systems.map((s) => s.id));
  assert.ok(starts.paper.every((s) => s.formulas) && starts.paper.some((s) => s.id === 'knife_edge'));
  assert.ok(!starts.paper.some((s) => s.id === sleigh.id), 'the sleigh has no paper’s form');
  // Without a form asked for: the paper's where there is one, else the general one.
  assert.equal(formOf(customFrom(catalog, 'knife_edge')), 'paper');
  const sys = customFrom(catalog, sleigh.id, { m: 3 });
  assert.ok(isGeneral(sys));
  assert.deepEqual(sys, { ...sleigh.general, parameters: { ...sleigh.general.parameters, m: 3 } });
  assert.equal(formOf(customFrom(catalog, 'knife_edge', {}, 'general')), 'general');
  // The vertical disk's invariants by name.
  assert.deepEqual(customFrom(catalog, disk.id).invariants, disk.general.invariants);
});

test('the general form offers the energy, the constraint and its invariants; the class’s energies only where it may be found', () => {
  const sys = customFrom(catalog, disk.id);
  assert.deepEqual(customIntegrals(sys), ['energy', 'passenger_energy', 'driver_energy', 'constraint', 'heading_rate', 'rolling_rate']);
  assert.deepEqual(defaultCustomIntegrals(sys), ['energy', 'constraint', 'heading_rate', 'rolling_rate']);
  assert.deepEqual(customIntegrals({ ...sys, detect_class: false }), ['energy', 'constraint', 'heading_rate', 'rolling_rate']);
  assert.deepEqual(coordinateNames(sys), ['x', 'y', 'phi', 'theta']);
});

test('a general-form system survives the round trip through the URL: diagonal, full and no mass', () => {
  const state = { ...defaultState(catalog, sleigh.id), system: structuredClone(SLEIGH), preset: '', params: {}, integrals: ['energy', 'constraint', 'kinetic'] };
  const query = encodeState(state, catalog);
  assert.ok(query.startsWith('custom=Chaplygin+sleigh&coordinates=x,y,theta&param.m=2&param.I=0.5&param.a=0.5&param.g=0&Mrow=m,0,0&Mrow=0,m,0&Mrow=0,0,I&V=m*g*y&A=-sin(theta),cos(theta),-a&inv.kinetic='), query);
  assert.deepEqual(decodeState(query, catalog).state, state);
  for (const mass of [['m', 'm', 'I'], undefined, [2, 1.5, 'I/2']]) {
    const sys = { ...structuredClone(SLEIGH), detect_class: false };
    if (mass) sys.mass = mass;
    else delete sys.mass;
    const back = decodeCustom(new URLSearchParams(encodeCustom(sys)));
    assert.deepEqual(back, sys, JSON.stringify(mass));
    assert.equal(massMode(back.mass), mass ? 'diagonal' : 'identity');
  }
  // As the request's `system`, unchanged.
  assert.deepEqual(requestBody(state).system, SLEIGH);
});

test("the editor's general-form inputs become the system object, or say what cannot be sent", () => {
  const fields = {
    name: 'Chaplygin sleigh',
    coordinates: ' x, y ,theta ',
    parameters: [['m', '2'], ['I', '0.5'], ['a', '0.5'], ['g', '0']],
    mass: { mode: 'full', rows: [['m', '0', '0'], ['0', ' m', '0'], ['0', '0', 'I']] },
    potential: 'm*g*y',
    constraints: [['-sin(theta)', 'cos(theta)', '-a']],
    invariants: [['kinetic', SLEIGH.invariants.kinetic]],
    detect_class: true,
  };
  const { system, invalid } = customFromFields(fields);
  assert.deepEqual(invalid, []);
  assert.deepEqual(system, SLEIGH);
  assert.deepEqual(customFromFields({ ...fields, mass: { mode: 'diagonal', rows: [['m', '1e0', 'I']] } }).system.mass, ['m', 1, 'I']);
  assert.ok(!('mass' in customFromFields({ ...fields, mass: { mode: 'identity', rows: [] } }).system));
  assert.ok(!('invariants' in customFromFields({ ...fields, invariants: [] }).system));
  const bad = customFromFields({ ...fields, invariants: [['', 'x'], ['k', 'x_dot'], ['k', 'y_dot']] });
  assert.deepEqual(bad.invalid, [
    { path: 'system.invariants', message: 'an invariant needs a name' },
    { path: 'system.invariants.k', message: "invariant 'k' is given twice" },
  ]);
});

test('the paper’s form written in the general one is the same system; back as far as it goes', () => {
  const knife = customFrom(catalog, 'knife_edge');
  const general = toGeneral(knife);
  assert.deepEqual(general.coordinates, ['x1', 'x2', 'zeta']);
  assert.deepEqual(general.constraints, knife.constraints.map((row) => [...row, '0']));
  assert.equal(general.potential, `(${knife.passenger_potential}) + (${knife.driver_potential})`);
  assert.equal(general.detect_class, true);
  const back = inForm(general, 'paper');
  assert.deepEqual([back.passenger, back.driver, back.constraints], [knife.passenger, knife.driver, knife.constraints]);
  assert.deepEqual(inForm(knife, 'paper'), knife);
});

test('a system outside the paper’s class keeps only the methods that apply', () => {
  const current = { ...defaultState(catalog, 'knife_edge', 'paper'), methods: [{ id: 'dd_avf', params: {} }, { id: 'leapfrog', params: {} }] };
  assert.deepEqual(ids(systemSwitched(catalog, current, sleigh.id).methods), ['leapfrog']);
  const onlyAvf = { ...current, methods: [{ id: 'dd_avf', params: {} }] };
  assert.deepEqual(ids(systemSwitched(catalog, onlyAvf, sleigh.id).methods), ids(defaultState(catalog, sleigh.id).methods));
  assert.deepEqual(ids(systemSwitched(catalog, current, 'contact_oscillator').methods), ['dd_avf', 'leapfrog']);
  // A scorecard's methods opened on the sleigh: DD-AVF left out.
  const opened = sceneOpened(catalog, { system: sleigh.id, preset: 'free' }, [{ id: 'dd_avf', label: 'DD-AVF' }, { id: 'rattle', label: 'RATTLE' }]);
  assert.deepEqual(ids(opened.methods), ['rattle']);
  // A link that names it: left out, with a warning.
  const { state, warnings } = decodeState(`system=${sleigh.id}&methods=dd_avf,dd`, catalog);
  assert.deepEqual(ids(state.methods), ['dd']);
  assert.match(warnings.join(), /Discrete derivative, average vector field \(DD-AVF\) does not apply to Chaplygin sleigh/);
  // A built-in's integrals by name; outside the class, no passenger or driver energy.
  assert.deepEqual(defaultState(catalog, sleigh.id).integrals, ['energy', 'constraint']);
  assert.deepEqual(defaultState(catalog, 'contact_oscillator').integrals, ['energy', 'passenger_energy', 'driver_energy', 'constraint', 'H_y']);
});

test('a built-in’s integrals go only where they are not all it lists: the scene’s own are measured', () => {
  // The vertical disk's heavy preset is outside the paper's class: no passenger or driver energy.
  const heavy = defaultState(catalog, disk.id, 'heavy');
  assert.deepEqual(heavy.integrals, disk.integrals);
  assert.ok(!('integrals' in requestBody(heavy, catalog)));
  assert.deepEqual(requestBody(heavy).integrals, disk.integrals, 'without the catalog, as listed');
  const some = { ...heavy, integrals: ['energy', 'heading_rate'] };
  assert.deepEqual(requestBody(some, catalog).integrals, ['energy', 'heading_rate']);
});

test('a preset may change the number of coordinates; the editor takes a start that fits', () => {
  const n1 = defaultState(catalog, 'chaotic_oscillator', 'n1');
  const n2 = presetSwitched(catalog, { ...n1, preset: 'n2' });
  assert.deepEqual([n2.params.n, n2.q.length, n2.v.length], [2, 5, 5]);
  assert.equal(decodeState(encodeState(n2, catalog), catalog).state.q.length, 5);
  // The general form (three coordinates at the defaults) with n = 2's state: n = 1's start.
  const custom = customized(catalog, n2);
  assert.equal(coordinateNames(custom.system).length, 3);
  assert.deepEqual([custom.q, custom.v], [n1.q, n1.v]);
  // "Start from" a form: that form, and the built-in's first preset.
  const started = startedFrom(catalog, n2, 'knife_edge', 'general');
  assert.ok(isGeneral(started.system));
  assert.deepEqual(started.q, defaultState(catalog, 'knife_edge').q);
  assert.deepEqual(started.integrals, ['energy', 'passenger_energy', 'driver_energy', 'constraint']);
});
