import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { sceneTitles, systemGroups } from '../src/scorecard/view.js';

const catalog = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));

// The scorecard's default scenes: the paper's six, then the literature's seven.
const integrals = (id) => catalog.systems.find((s) => s.id === id).integrals;
const scenes = [...catalog.paper_scenes, ...catalog.literature_scenes].map(({ system, preset }) => ({
  id: `${system}/${preset}`,
  scene: { system, preset, integrals: integrals(system) },
  runs: [],
}));

test('the thirteen default scenes group by system, in order', () => {
  assert.equal(scenes.length, 13);
  assert.deepEqual(
    systemGroups(scenes).map((g) => [g.system, g.scenes.length]),
    [
      ['knife_edge', 2],
      ['cvt_pendulum', 4],
      ['chaplygin_sleigh', 2],
      ['chaotic_oscillator', 1],
      ['contact_oscillator', 1],
      ['nonholonomic_oscillator', 1],
      ['heisenberg', 1],
      ['vertical_disk', 1],
    ],
  );
  // A system met again later is a group of its own.
  assert.equal(systemGroups([scenes[0], scenes[6], scenes[1]]).length, 3);
});

test('scene heads drop what their system’s labels share, and fall back to the preset id when far too wide', () => {
  const groups = systemGroups(scenes);
  const titles = groups.map((g) => sceneTitles(catalog, g.scenes));
  assert.deepEqual(titles[0], ['ε = 0', 'ε = 0.1']);
  assert.deepEqual(titles[1], ['oscillating driver, ε = 0', 'rotating driver, ε = 0', 'oscillating driver, ε = 0.5', 'rotating driver, ε = 0.5']);
  // Two integrals leave no room for "Free sleigh: turning ever slower".
  assert.deepEqual(titles[2], ['free', 'inclined']);
  // The vertical disk's six integrals have room for its label.
  assert.deepEqual(titles[7], ['ω_φ = 2, ω_θ = 1 to t = 100']);
  // A repeated scene keeps its index.
  const repeated = { ...scenes[0], id: 'knife_edge/paper#2' };
  assert.deepEqual(sceneTitles(catalog, [repeated]), ['knife edge, ε = 0 (2)']);
});
