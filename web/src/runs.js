// The runs table: one row per run with its colour, label, status, steps and compute time;
// a failed run gets a second row with the server's message, so a failure is never silent.

import { runColor } from './plots.js';

const STATUS = {
  running: 'running',
  ok: 'ok',
  failed: 'failed',
  cancelled: 'cancelled',
  interrupted: 'interrupted',
};

export function renderRuns(table, result) {
  table.hidden = result.runs.length === 0;
  const rows = [];
  result.runs.forEach((run, i) => {
    const tr = document.createElement('tr');
    tr.className = `run run-${run.status}`;
    tr.dataset.run = i;
    const name = cell('th');
    name.scope = 'row';
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = runColor(i);
    name.append(swatch, document.createTextNode(run.label));
    const state = cell('td');
    const badge = document.createElement('span');
    badge.className = `badge ${run.status}`;
    badge.textContent = run.status === 'running' ? `running ${Math.floor(run.fraction * 100)}%` : STATUS[run.status] ?? run.status;
    state.append(badge);
    tr.append(name, state, cell('td', 'num', run.steps === null ? '–' : run.steps.toLocaleString('en-US')), cell('td', 'num', timing(run)));
    rows.push(tr);
    if (run.status === 'failed') {
      const err = document.createElement('tr');
      err.className = 'run-error';
      const td = cell('td', '', run.error ?? 'failed without a message');
      td.colSpan = 4;
      err.append(td);
      rows.push(err);
    }
  });
  table.tBodies[0].replaceChildren(...rows);
}

function timing(run) {
  if (run.elapsed_ms === null) return '–';
  const ms = run.elapsed_ms;
  const time = ms < 1000 ? `${ms.toFixed(ms < 10 ? 1 : 0)} ms` : `${(ms / 1000).toFixed(2)} s`;
  if (!run.steps || !(ms > 0)) return time;
  const rate = run.steps / (ms / 1000);
  const shown = rate >= 1e6 ? `${(rate / 1e6).toFixed(1)} M` : rate >= 1e3 ? `${(rate / 1e3).toFixed(0)} k` : rate.toFixed(0);
  return `${time} · ${shown} steps/s`;
}

function cell(tag, className = '', text) {
  const c = document.createElement(tag);
  if (className) c.className = className;
  if (text !== undefined) c.textContent = text;
  return c;
}
