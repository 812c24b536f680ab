import { test } from 'node:test';
import assert from 'node:assert/strict';
import { ApiError, retrying } from '../src/data/api.js';

test('retrying waits out 503s and returns the first answer', async () => {
  let calls = 0;
  const waits = [];
  const answer = await retrying(
    async () => {
      calls += 1;
      if (calls < 3) throw new ApiError(503, 'busy', null, 0);
      return 'ok';
    },
    (wait) => waits.push(wait),
  );
  assert.equal(answer, 'ok');
  assert.equal(calls, 3);
  assert.deepEqual(waits, [0, 0]);
});

test('retrying throws any other failure at once', async () => {
  let calls = 0;
  const bad = new ApiError(422, 'step: must be positive', 'step', null);
  await assert.rejects(
    retrying(
      async () => {
        calls += 1;
        throw bad;
      },
      () => assert.fail('no retry for a 422'),
    ),
    bad,
  );
  assert.equal(calls, 1);
});

test('an abort during the wait for a retry ends it at once', async () => {
  const controller = new AbortController();
  let calls = 0;
  const started = Date.now();
  const pending = retrying(
    async () => {
      calls += 1;
      throw new ApiError(503, 'busy', null, 60);
    },
    () => setTimeout(() => controller.abort(), 10),
    controller.signal,
  );
  await assert.rejects(pending, { name: 'AbortError' });
  assert.equal(calls, 1, 'no second attempt after the abort');
  assert.ok(Date.now() - started < 30_000, 'the 60 s wait was not sat out');
});
