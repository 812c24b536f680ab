// The result of one simulation as it streams in: the resolved scene, then per run its status
// and its series, built by appending the `points` events. Exported as the JSON shape of
// `POST /simulate` (so a download equals what a script would get) and as long-format CSV.
// A run still going holds its steps so far and the time since the scene arrived (`live_ms`,
// from its `progress` events), which a cancelled run keeps. Where asked for, a run's sampled
// `observables` and its Poincaré `section` grow column by column from their events.

import { csvField } from './csv.js';

export class Result {
  /** `now()`: a clock in ms (injectable for tests). */
  constructor(scene, now = () => performance.now()) {
    this.scene = scene;
    this.now = now;
    this.started = now();
    const integrals = scene.integrals ?? [];
    this.runs = (scene.methods ?? []).map((method) => ({
      method,
      // The server labels every method of a scene; an unlabelled one is shown by its id.
      label: method.label ?? method.id,
      status: 'running',
      error: null,
      steps: null,
      elapsed_ms: null,
      cpu_ms: null,
      live_ms: null,
      t: null,
      fraction: 0,
      verdicts: null,
      gaps: {},
      series: Object.fromEntries(integrals.map((i) => [i, { t: [], mean: [], max: [] }])),
      observables: null,
      section: null,
    }));
  }

  /** Appends an `observables` event (`{run, t: [...], name: [...]}`). */
  addObservables(ev) {
    append(this.#run(ev.run), 'observables', ev);
  }

  /** Appends a `section` event (`{run, t: [...], x: [...]}`). */
  addSection(ev) {
    append(this.#run(ev.run), 'section', ev);
  }

  /** Appends a `points` event (scalars or arrays of new buckets). */
  addPoints(ev) {
    const run = this.#run(ev.run);
    const s = (run.series[ev.integral] ??= { t: [], mean: [], max: [] });
    for (const key of ['t', 'mean', 'max']) {
      const v = ev[key];
      if (Array.isArray(v)) for (const x of v) s[key].push(x);
      else s[key].push(v);
    }
  }

  /** Applies a `progress` event. */
  progress(ev) {
    const run = this.#run(ev.run);
    if (Number.isFinite(ev.fraction)) run.fraction = Math.min(1, Math.max(0, ev.fraction));
    if (Number.isFinite(ev.steps)) run.steps = ev.steps;
    if (Number.isFinite(ev.t)) run.t = ev.t;
    run.live_ms = this.now() - this.started;
  }

  /** Applies a `run` event (a run finished, or failed). */
  finishRun(ev) {
    const run = this.#run(ev.run);
    run.status = ev.status === 'ok' ? 'ok' : 'failed';
    run.error = ev.error ?? null;
    run.steps = ev.steps ?? null;
    run.elapsed_ms = ev.elapsed_ms ?? null;
    run.cpu_ms = ev.cpu_ms ?? null;
    run.verdicts = ev.verdicts ?? null;
    // Series with no values from some t on although the run went on, and why.
    run.gaps = ev.gaps ?? {};
    if (run.status === 'ok') run.fraction = 1;
  }

  /** Marks runs still going as cancelled (the user pressed Cancel or the stream broke); they
   *  keep their steps so far and the time they ran. */
  interrupt(status) {
    const ran = this.now() - this.started;
    for (const run of this.runs) {
      if (run.status !== 'running') continue;
      run.status = status;
      run.live_ms = ran;
    }
  }

  /** The time since the scene arrived, in ms. */
  get elapsed() {
    return this.now() - this.started;
  }

  /** Overall progress in [0, 1]: finished runs (ok or failed) count as complete, cancelled ones do not. */
  get fraction() {
    if (this.runs.length === 0) return 0;
    const sum = this.runs.reduce((a, r) => a + (r.status === 'ok' || r.status === 'failed' ? 1 : r.fraction), 0);
    return sum / this.runs.length;
  }

  /** The JSON response shape of `POST /simulate`. */
  toJSON() {
    return {
      scene: this.scene,
      runs: this.runs.map((r) => ({
        method: r.method,
        status: r.status,
        error: r.error,
        steps: r.steps,
        elapsed_ms: r.elapsed_ms,
        cpu_ms: r.cpu_ms,
        // As the JSON response: each series with its verdict and gap (from the `run` event).
        series: Object.fromEntries(
          Object.entries(r.series).map(([k, s]) => [k, { ...s, verdict: r.verdicts?.[k] ?? null, gap: r.gaps?.[k] ?? null }]),
        ),
        ...(r.observables ? { observables: r.observables } : {}),
        ...(r.section ? { section: r.section } : {}),
      })),
    };
  }

  /** One row per bucket: run, method, status, integral, t, mean, max. */
  toCSV() {
    const rows = ['run,method,status,integral,t,mean,max'];
    this.runs.forEach((r, i) => {
      for (const [integral, s] of Object.entries(r.series)) {
        for (let k = 0; k < s.t.length; k++) {
          rows.push([i, csvField(r.label), r.status, integral, num(s.t[k]), num(s.mean[k]), num(s.max[k])].join(','));
        }
      }
    });
    return rows.join('\n') + '\n';
  }

  #run(index) {
    const run = this.runs[index];
    if (!run) throw new Error(`the server sent an event for run ${index}, but the scene has ${this.runs.length} runs`);
    return run;
  }
}

// Appends an event's columns (every field but `run`) to the run's `part`.
function append(run, part, ev) {
  const cols = (run[part] ??= {});
  for (const [key, v] of Object.entries(ev)) {
    if (key === 'run') continue;
    const col = (cols[key] ??= []);
    if (Array.isArray(v)) for (const x of v) col.push(x);
    else col.push(v);
  }
}

function num(v) {
  return v === null || v === undefined ? '' : String(v);
}
