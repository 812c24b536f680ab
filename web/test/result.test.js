import assert from 'node:assert/strict';
import { test } from 'node:test';
import { Result } from '../src/data/result.js';

const scene = {
  system: 'knife_edge',
  preset: 'paper',
  integrals: ['energy'],
  methods: [{ id: 'dla', alpha: 0.4, label: 'DLA^0.4' }, { id: 'dd', label: 'DD' }],
};

test('points events concatenate into series, scalars or arrays', () => {
  const r = new Result(scene);
  r.addPoints({ run: 0, integral: 'energy', t: [1, 2], mean: [0.1, 0.2], max: [0.2, 0.3] });
  r.addPoints({ run: 0, integral: 'energy', t: 3, mean: 0.3, max: 0.4 });
  assert.deepEqual(r.runs[0].series.energy, { t: [1, 2, 3], mean: [0.1, 0.2, 0.3], max: [0.2, 0.3, 0.4] });
});

test('progress counts finished runs as complete and reaches 1', () => {
  const r = new Result(scene);
  r.progress({ run: 0, t: 50, fraction: 0.5 });
  assert.equal(r.fraction, 0.25);
  r.finishRun({ run: 0, status: 'failed', error: 'Newton did not converge at t = 3', steps: 10, elapsed_ms: 1 });
  r.finishRun({ run: 1, status: 'ok', error: null, steps: 318, elapsed_ms: 2, cpu_ms: 0.5 });
  assert.equal(r.fraction, 1);
  assert.equal(r.runs[0].status, 'failed');
  assert.equal(r.toJSON().runs[0].error, 'Newton did not converge at t = 3');
  assert.deepEqual([r.toJSON().runs[0].cpu_ms, r.toJSON().runs[1].cpu_ms], [null, 0.5]);
});

test('an event for a run the scene lacks is an error, not silence', () => {
  assert.throws(() => new Result(scene).addPoints({ run: 5, integral: 'energy', t: 1, mean: 0, max: 0 }), /run 5/);
});

test('cancel marks only unfinished runs', () => {
  const r = new Result(scene);
  r.finishRun({ run: 1, status: 'ok', steps: 1, elapsed_ms: 1 });
  r.progress({ run: 0, t: 1, fraction: 0.2 });
  r.interrupt('cancelled');
  assert.deepEqual(r.runs.map((x) => x.status), ['cancelled', 'ok']);
  assert.equal(r.fraction, 0.6, 'a cancelled run keeps the progress it made');
});

test('CSV has one row per bucket, labels quoted when needed', () => {
  const r = new Result({ ...scene, methods: [{ id: 'x', label: 'a,b' }] });
  r.addPoints({ run: 0, integral: 'energy', t: [1, 2], mean: [0, 1e-3], max: [0, 2e-3] });
  assert.equal(r.toCSV(), 'run,method,status,integral,t,mean,max\n0,"a,b",running,energy,1,0,0\n0,"a,b",running,energy,2,0.001,0.002\n');
});

test('runs take the labels the server gave their methods, else their ids', () => {
  assert.deepEqual(new Result(scene).runs.map((r) => r.label), ['DLA^0.4', 'DD']);
  const unlabelled = new Result({ ...scene, methods: [{ id: 'dla', alpha: 0.4 }, { id: 'leapfrog' }] });
  assert.deepEqual(unlabelled.runs.map((r) => r.label), ['dla', 'leapfrog']);
});

test('the run event carries the verdicts; the JSON download puts each on its series', () => {
  const r = new Result(scene);
  const verdict = { kind: 'drift', max: 2, early: 0.1, late: 1, ratio: 10 };
  r.addPoints({ run: 0, integral: 'energy', t: [1], mean: [0.5], max: [1] });
  r.finishRun({ run: 0, status: 'ok', steps: 1, elapsed_ms: 1, verdicts: { energy: verdict } });
  assert.deepEqual(r.runs[0].verdicts, { energy: verdict });
  assert.deepEqual(r.toJSON().runs[0].series.energy.verdict, verdict);
  assert.equal(r.toJSON().runs[1].series.energy.verdict, null, 'no verdict before the run ends');
});

test('progress carries the steps so far; a cancelled run keeps them and the time it ran', () => {
  let now = 1000;
  const r = new Result(scene, () => now);
  now = 3500;
  r.progress({ run: 0, t: 40, fraction: 0.4, steps: 128 });
  assert.deepEqual([r.runs[0].steps, r.runs[0].t, r.runs[0].live_ms], [128, 40, 2500]);
  now = 5000;
  assert.equal(r.elapsed, 4000);
  r.interrupt('cancelled');
  assert.deepEqual([r.runs[0].status, r.runs[0].steps, r.runs[0].live_ms], ['cancelled', 128, 4000]);
  assert.equal(r.runs[1].steps, null, 'a run without progress has no steps to show');
});

test('a series gap from the run event travels with the series, as in the JSON response', () => {
  const r = new Result(scene);
  const gap = { since: 72016.9, reason: 'passenger_at_rest', message: 'no value since t = 72017: the passenger is at rest' };
  r.finishRun({ run: 0, status: 'ok', steps: 1, elapsed_ms: 1, gaps: { energy: gap } });
  r.finishRun({ run: 1, status: 'ok', steps: 1, elapsed_ms: 1 });
  const json = r.toJSON();
  assert.deepEqual(json.runs[0].series.energy.gap, gap);
  assert.equal(json.runs[1].series.energy.gap, null);
  assert.deepEqual(r.runs[1].gaps, {});
});
