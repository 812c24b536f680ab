import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MARKS, PROPERTIES, consumed, propertyMark, runVerdicts, systemsOf, verdictTitle } from '../src/data/verdicts.js';

const methods = [{ id: 'dd', label: 'DD' }, { id: 'leapfrog', label: 'LF' }];
const prop = (method, system, scene, reversible, fibration) => ({
  method, system, scene, reversible, preserves_fibration: fibration,
  reversibility_defect: 1e-17, driver_coupling: fibration ? 0 : 3e-6, fiber_coupling: 0, constraint_defect: 1e-16, error: null,
});
// Scene-major, like the server: every method on scene 1, then on scene 2, …
const card = {
  methods,
  scenes: [
    { id: 'knife_edge/paper', scene: { system: 'knife_edge' } },
    { id: 'cvt_pendulum/oscillating', scene: { system: 'cvt_pendulum' } },
    { id: 'cvt_pendulum/rotating', scene: { system: 'cvt_pendulum' } },
  ],
  properties: [
    prop(methods[0], 'knife_edge', 'knife_edge/paper', true, true),
    prop(methods[1], 'knife_edge', 'knife_edge/paper', true, true),
    prop(methods[0], 'cvt_pendulum', 'cvt_pendulum/oscillating', true, false),
    prop(methods[1], 'cvt_pendulum', 'cvt_pendulum/oscillating', true, true),
    prop(methods[0], 'cvt_pendulum', 'cvt_pendulum/rotating', true, true),
    prop(methods[1], 'cvt_pendulum', 'cvt_pendulum/rotating', false, true),
  ],
};

test('scenes group by system in order of appearance', () => {
  assert.deepEqual(systemsOf(card), [
    ['knife_edge', ['knife_edge/paper']],
    ['cvt_pendulum', ['cvt_pendulum/oscillating', 'cvt_pendulum/rotating']],
  ]);
});

test("a method's property per system: yes, no or mixed over the system's scenes, numbers on hover", () => {
  assert.equal(propertyMark(card, 0, 'knife_edge', 'preserves_fibration').mark, 'yes');
  const dd = propertyMark(card, 0, 'cvt_pendulum', 'preserves_fibration');
  assert.equal(dd.mark, 'mixed');
  assert.match(dd.title, /driver coupling 3\.00e-6/);
  assert.equal(propertyMark(card, 1, 'cvt_pendulum', 'reversible').mark, 'mixed');
  assert.equal(propertyMark(card, 1, 'cvt_pendulum', 'preserves_fibration').mark, 'yes');
  const failed = { ...card, properties: card.properties.map((p) => ({ ...p, reversible: null, error: 'a step failed' })) };
  const unknown = propertyMark(failed, 0, 'knife_edge', 'reversible');
  assert.equal(unknown.mark, 'unknown');
  assert.match(unknown.title, /a step failed/);
});

test('a verdict title gives the numbers behind it; an infinite ratio is written ∞', () => {
  const t = verdictTitle({ kind: 'drift', max: 3.68, early: 0.0755, late: 3.29, ratio: 43.56 }, 'DLA^0.4: ');
  assert.equal(t, 'DLA^0.4: drift: max 3.68e+0, early max 7.55e-2, late mean 3.29e+0, late/early 43.56');
  assert.match(verdictTitle({ kind: 'drift', max: 1, early: 0, late: 1, ratio: null }), /late\/early ∞/);
  assert.match(verdictTitle(null), /no verdict/);
});

test('a run shows a verdict per integral: pending while it runs, none without data', () => {
  const integrals = ['energy', 'latitude'];
  const running = { label: 'LF', status: 'running', verdicts: null };
  assert.deepEqual(runVerdicts(running, integrals).map((v) => [v.short, v.kind, v.label]), [['H', 'pending', '…'], ['ℓ', 'pending', '…']]);
  const done = {
    label: 'DD',
    status: 'ok',
    verdicts: { energy: { kind: 'exact', max: 1e-15, early: 1e-15, late: 1e-15, ratio: 1 } },
  };
  const [energy, latitude] = runVerdicts(done, integrals);
  assert.deepEqual([energy.short, energy.kind, energy.label], ['H', 'exact', 'exact']);
  assert.match(energy.title, /^DD, energy: exact: max 1\.00e-15/);
  assert.deepEqual([latitude.kind, latitude.label], ['none', '–']);
  assert.match(latitude.title, /no verdict/);
});

test('a method without a step for the system is n/a, the fibration outside the class not defined', () => {
  const avf = { id: 'dd_avf', label: 'DD-AVF' };
  const lf = { id: 'leapfrog', label: 'LF' };
  const outside = (method, scene, measured) => ({
    method, system: 'chaplygin_sleigh', scene,
    reversible: measured ? true : null, symmetric: measured ? true : null, preserves_fibration: null,
    reversibility_defect: measured ? 1e-16 : null, symmetry_defect: measured ? 2e-16 : null,
    driver_coupling: null, fiber_coupling: null, constraint_defect: null,
    error: measured ? null : 'the method has no step for this system',
  });
  const why = "DD-AVF applies only to systems of the paper's class";
  const sleigh = {
    methods: [avf, lf],
    scenes: ['free', 'inclined'].map((p) => ({
      id: `chaplygin_sleigh/${p}`,
      scene: { system: 'chaplygin_sleigh' },
      runs: [{ status: 'not_applicable', error: why }, { status: 'ok' }],
    })),
    properties: ['free', 'inclined'].flatMap((p) => [outside(avf, `chaplygin_sleigh/${p}`, false), outside(lf, `chaplygin_sleigh/${p}`, true)]),
  };
  for (const property of ['reversible', 'symmetric', 'preserves_fibration']) {
    const na = propertyMark(sleigh, 0, 'chaplygin_sleigh', property);
    assert.equal(na.mark, 'not_applicable', property);
    assert.ok(na.title.includes(why), na.title);
  }
  assert.equal(propertyMark(sleigh, 1, 'chaplygin_sleigh', 'reversible').mark, 'yes');
  const sym = propertyMark(sleigh, 1, 'chaplygin_sleigh', 'symmetric');
  assert.equal(sym.mark, 'yes');
  assert.match(sym.title, /defect 2\.00e-16/);
  const fib = propertyMark(sleigh, 1, 'chaplygin_sleigh', 'preserves_fibration');
  assert.equal(fib.mark, 'not_defined');
  assert.match(fib.title, /not defined outside the paper’s class/);
  assert.equal(MARKS[fib.mark][0], '–');
  assert.deepEqual(PROPERTIES.map((p) => p.id), ['reversible', 'symmetric', 'preserves_fibration']);
});

test('a drift of a consumed integral says why its ratio is 1', () => {
  // DLA^0.4's passenger energy on the rotating CVT to t = 1e6: gone within the early window.
  const drained = { kind: 'drift', max: 1, early: 1, late: 1, ratio: 1 };
  assert.ok(consumed(drained));
  assert.match(verdictTitle(drained), /late\/early 1\.00 — the integral is consumed/);
  const growing = { kind: 'drift', max: 1, early: 0.1, late: 0.9, ratio: 9 };
  assert.ok(!consumed(growing));
  assert.doesNotMatch(verdictTitle(growing), /consumed/);
  assert.ok(!consumed({ kind: 'bounded', max: 1, early: 1, late: 0.5, ratio: 0.5 }));
  assert.ok(!consumed({ kind: 'drift', max: 1, early: 0, late: 1, ratio: null }));
});
