import assert from 'node:assert/strict';
import { test } from 'node:test';
import { timing } from '../src/data/timing.js';

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

test('a running run shows its time so far and the time left; a cancelled one keeps its time', async () => {
  const { clock, eta, progressNote, runsLeft } = await import('../src/data/timing.js');
  assert.equal(eta(10_000, 0.25), 30_000);
  assert.equal(eta(10_000, 0), null, 'no estimate without progress');
  assert.equal(eta(100, 0.5), null, 'no estimate in the first half second');
  assert.equal(eta(10_000, 1), null);
  assert.deepEqual([450, 12_300, 200_000, 3_900_000].map(clock), ['450 ms', '12 s', '3 min 20 s', '1 h 05 min']);
  assert.equal(progressNote(10_000, 30_000), '10 s elapsed, about 30 s left');
  assert.equal(progressNote(200, null), '200 ms elapsed');
  // The request's time left is its slowest run's, each at its own pace: one run nearly done
  // and one a fifth of the way does not read "a few seconds left".
  const runs = [
    { status: 'running', live_ms: 8_000, fraction: 0.9 },
    { status: 'running', live_ms: 8_000, fraction: 0.25 },
    { status: 'ok', live_ms: 2_000, fraction: 1 },
  ];
  assert.equal(runsLeft(runs), 24_000);
  assert.equal(timing(runs[1]).text, '8 s, ~24 s left', 'the run and the request agree');
  assert.equal(runsLeft([{ status: 'running', live_ms: 8_000, fraction: 0 }, runs[0]]), null, 'a run without an estimate yet');
  assert.equal(runsLeft([runs[2]]), null);
  assert.equal(timing({ status: 'running', live_ms: 10_000, fraction: 0.5, elapsed_ms: null }).text, '10 s, ~10 s left');
  const cancelled = timing({ status: 'cancelled', live_ms: 4_000, fraction: 0.5, elapsed_ms: null, steps: 1200 });
  assert.equal(cancelled.text, '4 s (partial)');
  assert.match(cancelled.title, /cancelled/);
});
