// Talking to the server: the catalog (`GET /systems`), the streamed simulation and sweep
// (`POST /simulate` and `POST /sweep` with `Accept: text/event-stream`), the scorecard and
// work–precision (JSON). Browsers' EventSource only does GET,
// so the stream is read with fetch and parsed by eventsource-parser; cancelling is aborting
// the fetch, which closes the connection and stops the computation on the server.

import { EventSourceParserStream } from 'eventsource-parser/stream';

/** An error response of the API: `{"error", "path"}` with its HTTP status. */
export class ApiError extends Error {
  constructor(status, message, path, retryAfter) {
    super(message);
    this.name = 'ApiError';
    this.status = status;
    this.path = path ?? null;
    this.retryAfter = retryAfter ?? null;
  }
}

async function errorFrom(response) {
  let body = null;
  try {
    body = await response.json();
  } catch {
    // Not JSON (a proxy's page, say): fall back to the status line.
  }
  const message = body?.error ?? `${response.status} ${response.statusText || 'error'}`;
  const retry = Number(response.headers.get('Retry-After'));
  return new ApiError(response.status, message, body?.path, Number.isFinite(retry) && retry > 0 ? retry : null);
}

/** `GET /systems`. */
export async function fetchCatalog() {
  const response = await fetch('systems', { headers: { Accept: 'application/json' } });
  if (!response.ok) throw await errorFrom(response);
  return response.json();
}

/**
 * `POST /simulate`, streamed: calls `onEvent(name, data)` for every event until the stream
 * ends. Rejects with an ApiError for a 4xx/5xx answer, with an AbortError when `signal` aborts.
 */
export function simulate(body, options) {
  return stream('simulate', body, options);
}

/** `POST /sweep`, streamed (`start`, `cell`, `progress`, `done` events), as `simulate`. */
export function sweep(body, options) {
  return stream('sweep', body, options);
}

async function stream(path, body, { signal, onEvent }) {
  const response = await fetch(path, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json', Accept: 'text/event-stream' },
    body: JSON.stringify(body),
    signal,
  });
  if (!response.ok) throw await errorFrom(response);
  if (!response.body) throw new Error('the server sent no stream');
  const events = response.body
    .pipeThrough(new TextDecoderStream())
    .pipeThrough(new EventSourceParserStream({ onError: 'terminate' }));
  const reader = events.getReader();
  for (;;) {
    const { value, done } = await reader.read();
    if (done) return;
    const data = value.data === '' ? null : JSON.parse(value.data);
    onEvent(value.event ?? 'message', data);
  }
}

/** `POST path` with a JSON body and a JSON answer; rejects with an ApiError for a 4xx/5xx. */
async function postJson(path, body, { signal } = {}) {
  const response = await fetch(path, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json', Accept: 'application/json' },
    body: JSON.stringify(body),
    signal,
  });
  if (!response.ok) throw await errorFrom(response);
  return response.json();
}

/** `POST /scorecard` (JSON). Rejects with an ApiError for a 4xx/5xx answer. */
export function fetchScorecard(body, options) {
  return postJson('scorecard', body, options);
}

/** `POST /work-precision` (JSON). Rejects with an ApiError for a 4xx/5xx answer. */
export function fetchWorkPrecision(body, options) {
  return postJson('work-precision', body, options);
}

/** Seconds to wait before retrying a 503 (the server's `Retry-After`, else 1). */
export function retryAfter(error) {
  return error instanceof ApiError && error.status === 503 ? error.retryAfter ?? 1 : null;
}

/** Runs `attempt` until it does not fail with a 503, calling `onWait(seconds)` before each
 *  retry; any other failure (an abort included) is thrown. An abort of `signal` during a
 *  wait ends the wait at once with an `AbortError`. */
export async function retrying(attempt, onWait, signal) {
  for (;;) {
    try {
      return await attempt();
    } catch (e) {
      const wait = retryAfter(e);
      if (wait === null) throw e;
      onWait(wait);
      await pause(wait * 1000, signal);
    }
  }
}

// Waits `ms`, or rejects with an `AbortError` as soon as `signal` aborts.
function pause(ms, signal) {
  return new Promise((resolve, reject) => {
    const aborted = () => reject(new DOMException('The wait was aborted.', 'AbortError'));
    if (signal?.aborted) return aborted();
    const timer = setTimeout(() => {
      signal?.removeEventListener('abort', onAbort);
      resolve();
    }, ms);
    const onAbort = () => {
      clearTimeout(timer);
      aborted();
    };
    signal?.addEventListener('abort', onAbort, { once: true });
  });
}
