import assert from 'node:assert/strict';
import { test } from 'node:test';
import { timing } from '../src/timing.js';

test('the speed is per second of CPU time, both times in the title', () => {
  const t = timing({ steps: 30000, elapsed_ms: 53, cpu_ms: 3.75 });
  assert.equal(t.text, '3.8 ms CPU · 8.0 M steps/s');
  assert.match(t.title, /CPU time 3\.8 ms; wall-clock time 53 ms/);
});

test('without a CPU time, the wall time and its speed', () => {
  assert.deepEqual(timing({ steps: 318, elapsed_ms: 2, cpu_ms: null }), {
    text: '2.0 ms · 159 k steps/s',
    title: 'wall-clock time 2.0 ms',
  });
  assert.equal(timing({ steps: 10, elapsed_ms: 1500 }).text, '1.50 s · 7 steps/s');
});

test('a running run shows a dash; a run of no steps shows only its time', () => {
  assert.equal(timing({ steps: null, elapsed_ms: null, cpu_ms: null }).text, '–');
  assert.equal(timing({ steps: 0, elapsed_ms: 0.5, cpu_ms: 0.25 }).text, '0.3 ms CPU');
});
