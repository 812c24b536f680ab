import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { fieldLabel, humanLabel } from '../src/data/labels.js';
import { sceneCaption, sceneStem, systemSlug } from '../src/data/custom.js';

const catalog = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));

test('method labels: TeX-like exponents become superscripts', () => {
  assert.equal(humanLabel('DLA^{0,1}'), 'DLA⁰˒¹');
  assert.equal(humanLabel('DLA^0.4'), 'DLA⁰·⁴');
  assert.equal(humanLabel('DLA^0.5∘p4s3'), 'DLA⁰·⁵∘p4s3');
  assert.equal(humanLabel('LF'), 'LF');
  assert.equal(humanLabel('X^{ab}'), 'X^(ab)', 'no superscript for every character: plain, without braces');
  assert.equal(humanLabel(undefined), '');
  // Every default method of the catalog gets a label without braces or carets.
  for (const m of catalog.default_methods) assert.doesNotMatch(humanLabel(m.label), /[{}^]/);
});

test('API field paths read as the labels the page shows', () => {
  assert.equal(fieldLabel('levels'), 'Step sizes');
  assert.equal(fieldLabel('steps'), 'Steps h');
  assert.equal(fieldLabel('steps[2]'), 'Steps h, entry 3');
  assert.equal(fieldLabel('repeats'), 'Repeats');
  assert.equal(fieldLabel('step'), 'Step h');
  assert.equal(fieldLabel('t_end'), 'Final time');
  assert.equal(fieldLabel('q[2]'), 'q(0), entry 3');
  assert.equal(fieldLabel('params.epsilon'), 'ε (epsilon)');
  assert.equal(fieldLabel('params.k'), 'k');
  assert.equal(fieldLabel('methods[1].alpha'), 'method 2, α');
  assert.equal(fieldLabel('methods[0]'), 'method 1');
  assert.equal(fieldLabel('methods'), 'Methods');
  assert.equal(fieldLabel('system.constraints[0][1]'), 'System (constraints[0][1])');
  assert.equal(fieldLabel(null), null);
});

test('a scene is named for people and for files', () => {
  const scene = { system: 'knife_edge', preset: 'paper', params: { epsilon: 0 }, step: 0.1, t_end: 20 };
  assert.equal(sceneCaption(scene, catalog), 'Knife edge (skate on an inclined plane) · knife edge, ε = 0 · h = 0.1 · t_end = 20');
  assert.equal(sceneStem(scene, catalog), 'nhlab-knife_edge-paper');
  assert.match(sceneCaption({ ...scene, step: Math.PI / 10 }, catalog), / · h = 0\.314159 · /, 'a step in six digits');
  const custom = { system: { name: 'My Toy (v2)', passenger: ['x', 'y'], driver: 'z', parameters: {}, constraints: [] } };
  assert.equal(sceneStem(custom, catalog), 'nhlab-my-toy-v2');
  assert.equal(sceneStem({ system: { name: '' } }, catalog), 'nhlab-custom-system');
});

test('a system in a file name: a built-in by its id, a custom one by its name', () => {
  assert.equal(systemSlug('cvt_pendulum', catalog), 'cvt_pendulum');
  assert.equal(systemSlug({ name: ' Skate, in a bowl! ' }, catalog), 'skate-in-a-bowl');
  assert.equal(systemSlug({ name: '***' }, catalog), 'custom');
});

test('a swept method is named by what is swept, not by the value it was listed with', async () => {
  const { sweptLabel, fieldLabel } = await import('../src/data/labels.js');
  assert.equal(sweptLabel('M^0.5', ['methods.alpha', 'params.epsilon'], 0), 'M (α swept)');
  assert.equal(sweptLabel('M^0.5', ['methods[1].alpha'], 0), 'M⁰·⁵', 'the axis sets another method');
  assert.equal(sweptLabel('M^0.5', ['methods[1].alpha'], 1), 'M (α swept)');
  assert.equal(sweptLabel('L', ['params.epsilon'], 0), 'L');
  assert.equal(fieldLabel('methods.alpha'), 'α (every method)');
  assert.equal(fieldLabel('step'), 'Step h');
});
