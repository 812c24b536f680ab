import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import {
  defaultMethods,
  defaultWindow,
  figureIntegrals,
  figureScenes,
  methodsFor,
  paperClassLine,
  paperExperiments,
  paperFigures,
  panelTitles,
  presetLabel,
  systemShortName,
} from '../src/data/catalog.js';
import { defaultState } from '../src/data/state.js';

// GET /systems as the server answers it.
const catalog = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));

test('the default methods are the catalog default_methods', () => {
  const methods = defaultMethods(catalog);
  assert.equal(methods.length, catalog.default_methods.length);
  catalog.default_methods.forEach((view, i) => {
    assert.equal(methods[i].id, view.id);
    const info = catalog.methods.find((m) => m.id === view.id);
    assert.deepEqual(Object.keys(methods[i].params), info.params.map((p) => p.name).filter((n) => n in view));
    for (const [name, value] of Object.entries(methods[i].params)) assert.equal(value, view[name]);
  });
  // A `params` object is read as well as inline values; unknown methods are left out.
  const nested = { ...catalog, default_methods: [{ id: catalog.methods[0].id, params: { [catalog.methods[0].params[0]?.name ?? 'x']: 0.25 } }, { id: 'no-such-method' }] };
  const [only, ...rest] = defaultMethods(nested);
  assert.equal(rest.length, 0);
  assert.equal(only.id, catalog.methods[0].id);
});

test('the figure integrals follow from the system: split energies and latitude, else the energy', () => {
  assert.deepEqual(figureIntegrals({ integrals: ['energy', 'passenger_energy', 'driver_energy', 'constraint'] }), ['energy']);
  assert.deepEqual(figureIntegrals({ integrals: ['energy', 'passenger_energy', 'driver_energy', 'latitude', 'constraint'] }), ['passenger_energy', 'driver_energy', 'latitude']);
  assert.deepEqual(figureIntegrals({ integrals: ['constraint', 'foo'] }), ['foo']);
  assert.deepEqual(figureIntegrals(undefined), []);
});

test('the default window is 3 % of the decade of t_end', () => {
  assert.equal(defaultWindow(100), 3);
  assert.equal(defaultWindow(999), 3);
  assert.equal(defaultWindow(1000), 30);
  assert.equal(defaultWindow(3000), 30);
  assert.equal(defaultWindow(10), 0.3);
  assert.equal(defaultWindow(1), 0.03);
  assert.equal(defaultWindow(2e4), 300);
  assert.equal(defaultWindow(null), 3);
  assert.equal(defaultWindow(-1), 3);
  assert.equal(defaultWindow(NaN), 3);
});

test('the paper experiments are the paper scenes, with the paper figures integrals and windows', () => {
  const experiments = paperExperiments(catalog);
  assert.deepEqual(experiments.map((x) => [x.system, x.preset]), catalog.paper_scenes.map((s) => [s.system, s.preset]));
  // What the page hard-coded before, now derived: the knife edge shows its energy with a
  // window of 3, the pendulum-driven CVT its split energies and latitude with a window of 30.
  assert.deepEqual(
    experiments.map((x) => [x.system, x.preset, x.integrals, x.window]),
    [
      ['knife_edge', 'paper', ['energy'], 3],
      ['knife_edge', 'paper-perturbed', ['energy'], 3],
      ...['oscillating', 'rotating', 'oscillating-perturbed', 'rotating-perturbed'].map((p) => ['cvt_pendulum', p, ['passenger_energy', 'driver_energy', 'latitude'], 30]),
    ],
  );
  for (const x of experiments) assert.doesNotMatch(x.label, /^Paper:/);
  // A scene the catalog cannot resolve is left out.
  assert.equal(paperExperiments({ ...catalog, paper_scenes: [{ system: 'nope', preset: 'x' }, catalog.paper_scenes[0]] }).length, 1);
  assert.deepEqual(paperExperiments({ ...catalog, paper_scenes: undefined }), []);
});

test('every preset gets the window of its final time; the paper presets keep theirs', () => {
  for (const system of catalog.systems) {
    for (const preset of system.presets) {
      assert.equal(defaultState(catalog, system.id, preset.id).window, defaultWindow(preset.t_end));
    }
  }
  assert.equal(defaultState(catalog, 'knife_edge', 'paper').window, 3);
  assert.equal(defaultState(catalog, 'cvt_pendulum', 'rotating').window, 30);
});

test('short names, preset labels and panel titles', () => {
  assert.equal(systemShortName({ id: 'a', name: 'Knife edge (skate on an inclined plane)' }), 'Knife edge');
  assert.equal(systemShortName({ id: 'b', name: 'CVT, pendulum driver' }), 'CVT');
  assert.equal(systemShortName({ id: 'c', name: '' }), 'c');
  assert.equal(presetLabel({ id: 'p', label: 'Paper: knife edge, ε = 0' }), 'knife edge, ε = 0');
  assert.equal(presetLabel({ id: 'p' }), 'p');
  assert.deepEqual(panelTitles(['knife edge, ε = 0', 'knife edge, ε = 0.1']), ['ε = 0', 'ε = 0.1']);
  assert.deepEqual(panelTitles(['oscillating driver, ε = 0', 'rotating driver, ε = 0']), ['oscillating driver, ε = 0', 'rotating driver, ε = 0']);
  assert.deepEqual(panelTitles(['a, b', 'a, b']), ['b', 'b']);
  assert.deepEqual(panelTitles(['alone, here']), ['alone, here']);
});

test('the paper figures: a figure per system and integral, a panel per scene', () => {
  const figures = paperFigures(catalog);
  assert.deepEqual(
    figures.map((f) => [f.id, f.title, f.panels.length, [...new Set(f.panels.map((p) => p.window))]]),
    [
      ['knife_edge-energy', 'Knife edge: energy error |H − H(0)|', 2, [3]],
      ['cvt_pendulum-passenger_energy', 'CVT: passenger energy error |E − E(0)|', 4, [30]],
      ['cvt_pendulum-driver_energy', 'CVT: driver energy error |h − h(0)|', 4, [30]],
      ['cvt_pendulum-latitude', 'CVT: latitude error |ℓ − ℓ(0)| (hidden integral, at the section crossings)', 4, [30]],
    ],
  );
  assert.deepEqual(figures[0].panels.map((p) => p.title), ['ε = 0', 'ε = 0.1']);
  assert.deepEqual(figures[1].panels.map((p) => p.title), ['oscillating driver, ε = 0', 'rotating driver, ε = 0', 'oscillating driver, ε = 0.5', 'rotating driver, ε = 0.5']);
  // Each scene is streamed once, with every integral its figures show.
  assert.deepEqual(
    figureScenes(figures).map((s) => [s.system, s.preset, s.integrals]),
    paperExperiments(catalog).map((x) => [x.system, x.preset, x.integrals]),
  );
});

test('the page sources name no system and no method', async () => {
  const { readdirSync } = await import('node:fs');
  const dir = new URL('../src/', import.meta.url);
  const escape = (t) => t.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
  // Ids as words (`knife_edge`, `dd`), labels as whole tokens (`DLA^0.4`, `LF`).
  const names = [
    ...catalog.systems.map((s) => s.id),
    ...catalog.methods.filter((m) => !m.instrument).map((m) => m.id),
    ...catalog.default_methods.map((m) => m.label),
  ];
  // An instrument's id (`reference`) is an English word too: only as a quoted literal.
  const instruments = catalog.methods.filter((m) => m.instrument).map((m) => m.id);
  for (const file of readdirSync(dir, { recursive: true }).filter((f) => /\.(js|html|css)$/.test(f))) {
    const text = readFileSync(new URL(file, dir), 'utf8');
    for (const name of names) {
      assert.doesNotMatch(text, new RegExp(`(?<![\\w^])${escape(name)}(?![\\w^])`), `${file} names "${name}"`);
    }
    for (const id of instruments) assert.doesNotMatch(text, new RegExp(`['"\`]${escape(id)}['"\`]`), `${file} names "${id}"`);
  }
});

test("a system offers the methods that apply to it and says whether it is in the paper's class", () => {
  const all = catalog.methods.map((m) => m.id);
  assert.deepEqual(methodsFor(catalog, 'knife_edge').map((m) => m.id), all);
  assert.deepEqual(methodsFor(catalog, 'chaplygin_sleigh').map((m) => m.id), all.filter((id) => id !== 'dd_avf'));
  // A custom system: every method (the server says which do not apply).
  assert.deepEqual(methodsFor(catalog, { name: 'mine' }).map((m) => m.id), all);
  const find = (id) => catalog.systems.find((s) => s.id === id);
  assert.equal(paperClassLine(find('contact_oscillator').paper_class), 'In the paper’s class, driver y.');
  assert.equal(paperClassLine(find('heisenberg').paper_class), "Outside the paper’s class: A depends on x and y (the paper's class: on the driver alone).");
  assert.equal(paperClassLine({ member: false, driver: null, why_not: 'M ≠ I.' }, ' (here)'), 'Outside the paper’s class (here): M ≠ I.');
  assert.equal(paperClassLine({ member: true, driver: 'y', why_not: null }, ' (here)'), 'In the paper’s class (here), driver y.');
  assert.equal(paperClassLine({ member: true, driver: null, why_not: null }), 'In the paper’s class.');
  assert.equal(paperClassLine(null), '');
});

test('compositions are offered where the method as configured is symmetric, with its order', async () => {
  const { composableAt } = await import('../src/data/catalog.js');
  const dla = catalog.methods.find((m) => m.symmetric_at);
  assert.ok(dla, 'a method symmetric at one parameter value');
  const { param, value, order_elsewhere: elsewhere } = dla.symmetric_at;
  assert.deepEqual(composableAt(dla, { [param]: value }), { composable: true, order: dla.order });
  assert.deepEqual(composableAt(dla, { [param]: value - 0.1 }), { composable: false, order: elsewhere });
  assert.deepEqual(composableAt(dla, {}), { composable: dla.params.find((p) => p.name === param).default === value, order: dla.params.find((p) => p.name === param).default === value ? dla.order : elsewhere });
  const plain = catalog.methods.find((m) => m.composable && !m.symmetric_at);
  assert.deepEqual(composableAt(plain, {}), { composable: true, order: plain.order });
  const never = catalog.methods.find((m) => !m.composable);
  assert.equal(composableAt(never, {}).composable, false);
});

test('a PRK method: its tableau and constraint give its order and whether it may be composed', async () => {
  const { composableAt, findTableau, tableauChoice, tableauMethod, takesTableau } = await import('../src/data/catalog.js');
  // The method the tableaux are for, the one GET /systems marks by_tableau (the page names no method).
  assert.equal(tableauMethod(catalog), 'prk');
  assert.ok(takesTableau(catalog, 'prk'));
  assert.ok(!takesTableau(catalog, 'spark'));
  assert.equal(tableauMethod({ ...catalog, tableaux: [] }), undefined);
  const prk = catalog.methods.find((m) => m.id === 'prk');
  const at = (tableau, constraint) => composableAt(prk, {}, tableauChoice(catalog, tableau, constraint).entry);
  // Gauss with its stage conditions is not symmetric; at the step's end or midpoint it is,
  // of order 2. Lobatto IIIA–IIIB is symmetric with each, Radau IIA with none.
  assert.deepEqual(at('gauss3', 'stage'), { composable: false, order: 6 });
  assert.deepEqual(at('gauss2', 'midpoint'), { composable: true, order: 2 });
  assert.deepEqual(at('lobatto3', 'stage'), { composable: true, order: 4 });
  assert.deepEqual(at('radau2', 'end'), { composable: false, order: 2 });
  // The numbers are the catalog's, for every tableau and constraint.
  for (const t of catalog.tableaux) {
    for (const c of t.constraints) assert.deepEqual(at(t.id, c.id), { composable: c.symmetric, order: c.order }, `${t.id}, ${c.id}`);
  }
  // Without a choice: the server's default, gauss2 with stage, which is what `composable` says.
  assert.deepEqual(tableauChoice(catalog), { tableau: 'gauss2', constraint: 'stage', entry: findTableau(catalog, 'gauss2').constraints[0] });
  assert.deepEqual(at(undefined, undefined), { composable: prk.composable, order: prk.order });
  assert.deepEqual(composableAt(prk, {}), { composable: false, order: prk.order });
  // An unknown tableau falls back to the default, keeping a constraint it takes; a constraint
  // the tableau does not take falls back to `stage`.
  assert.deepEqual(tableauChoice(catalog, 'gauss9', 'midpoint').tableau, 'gauss2');
  assert.deepEqual(tableauChoice(catalog, 'gauss9', 'midpoint').constraint, 'midpoint');
  assert.deepEqual(tableauChoice(catalog, 'lobatto2', 'somewhere').constraint, 'stage');
  const endOnly = { ...catalog, tableaux: [{ id: 'mine', order: 2, constraints: [{ id: 'end', order: 2, symmetric: true, label: 'PRK[mine, end]' }] }] };
  assert.deepEqual(tableauChoice(endOnly, 'mine').constraint, 'end');
});
