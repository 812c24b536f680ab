// How long a run took, for the runs table. The speed is steps per second of the run's CPU
// time (`cpu_ms`), which measures the method: its wall time (`elapsed_ms`) also counts the
// time it waited for a core, which five runs on a small machine, or this page drawing its
// plots on the same machine, make most of it. Both times are in the cell's title. While a
// run goes, the cell shows the time since it started and an estimate of the time left (from
// the stream's `progress` events); a cancelled run keeps the time it ran.

/** `{ text, title }` of a run's time cell: the elapsed time and what is left while it runs,
 *  the time it ran when cancelled, else its CPU (or wall) time and speed. */
export function timing(run) {
  const wall = run.elapsed_ms;
  const live = run.live_ms;
  if ((wall === null || wall === undefined) && Number.isFinite(live)) {
    if (run.status === 'running') {
      const left = eta(live, run.fraction);
      return { text: left === null ? clock(live) : `${clock(live)}, ~${clock(left)} left`, title: `wall-clock time so far ${clock(live)}${left === null ? '' : `; about ${clock(left)} left at this pace`}` };
    }
    return { text: `${clock(live)} (partial)`, title: `wall-clock time until the run was ${run.status}; the steps are those done by then` };
  }
  if (wall === null || wall === undefined) return { text: '–', title: '' };
  const cpu = Number.isFinite(run.cpu_ms) ? run.cpu_ms : null;
  const ms = cpu ?? wall;
  const text = cpu === null ? duration(wall) : `${duration(cpu)} CPU`;
  const title = cpu === null
    ? `wall-clock time ${duration(wall)}`
    : `CPU time ${duration(cpu)}; wall-clock time ${duration(wall)} (the runs share the server's cores)`;
  if (!run.steps || !(ms > 0)) return { text, title };
  const rate = run.steps / (ms / 1000);
  const shown = rate >= 1e6 ? `${(rate / 1e6).toFixed(1)} M` : rate >= 1e3 ? `${(rate / 1e3).toFixed(0)} k` : rate.toFixed(0);
  return { text: `${text} · ${shown} steps/s`, title };
}

function duration(ms) {
  return ms < 1000 ? `${ms.toFixed(ms < 10 ? 1 : 0)} ms` : `${(ms / 1000).toFixed(2)} s`;
}

/** The time left at the pace so far, in ms: null before 1 % or 0.5 s, or once done. */
export function eta(elapsedMs, fraction) {
  if (!(fraction >= 0.01) || fraction >= 1 || !(elapsedMs >= 500)) return null;
  return (elapsedMs * (1 - fraction)) / fraction;
}

/** A duration for people: `850 ms`, `12 s`, `3 min 20 s`, `1 h 05 min`. */
export function clock(ms) {
  if (!Number.isFinite(ms) || ms < 0) return '–';
  if (ms < 1000) return `${Math.round(ms)} ms`;
  const s = Math.round(ms / 1000);
  if (s < 60) return `${s} s`;
  if (s < 3600) return `${Math.floor(s / 60)} min ${String(s % 60).padStart(2, '0')} s`;
  return `${Math.floor(s / 3600)} h ${String(Math.floor((s % 3600) / 60)).padStart(2, '0')} min`;
}

/** The time left of a request's runs, in ms: the slowest running run's (the runs go in
 *  parallel, so the request ends with its last run), each at its own pace; null while a
 *  running run has no estimate yet, or none runs. */
export function runsLeft(runs) {
  let left = null;
  for (const run of runs) {
    if (run.status !== 'running') continue;
    const mine = eta(run.live_ms, run.fraction);
    if (mine === null) return null;
    left = Math.max(left ?? 0, mine);
  }
  return left;
}

/** A status note on a long computation: `12 s elapsed, about 20 s left` (`leftMs` null: no
 *  estimate yet). */
export function progressNote(elapsedMs, leftMs) {
  return `${clock(elapsedMs)} elapsed${leftMs === null || leftMs === undefined ? '' : `, about ${clock(leftMs)} left`}`;
}
