// How long a run took, for the runs table. The speed is steps per second of the run's CPU
// time (`cpu_ms`), which measures the method: its wall time (`elapsed_ms`) also counts the
// time it waited for a core, which five runs on a small machine, or this page drawing its
// plots on the same machine, make most of it. Both times are in the cell's title.

/** `{ text, title }` of a finished run's time cell; `–` while it runs. */
export function timing(run) {
  const wall = run.elapsed_ms;
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
