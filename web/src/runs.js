// The runs table: one row per run with its colour, label, status, the verdict of each of its
// series (exact / bounded / drift, the numbers on hover), steps and time (`timing`); a failed
// run gets a second row with the server's message, so a failure is never silent.

import { runColor } from './plots.js';
import { timing } from './timing.js';
import { runVerdicts } from './verdicts.js';

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
    tr.append(name, state, verdictsCell(run, result.scene.integrals ?? []), cell('td', 'num', run.steps === null ? '–' : run.steps.toLocaleString('en-US')), timeCell(run));
    rows.push(tr);
    if (run.status === 'failed') {
      const err = document.createElement('tr');
      err.className = 'run-error';
      const td = cell('td', '', run.error ?? 'failed without a message');
      td.colSpan = 5;
      err.append(td);
      rows.push(err);
    }
  });
  table.tBodies[0].replaceChildren(...rows);
}

function verdictsCell(run, integrals) {
  const td = cell('td', 'verdicts');
  const list = cell('div', 'verdicts-list');
  td.append(list);
  for (const v of runVerdicts(run, integrals)) {
    const chip = cell('span', `verdict-chip ${v.kind}`);
    chip.dataset.integral = v.integral;
    chip.dataset.kind = v.kind;
    chip.title = v.title;
    chip.append(cell('span', 'chip-label', v.short), cell('span', 'chip-kind', v.label));
    list.append(chip);
  }
  return td;
}

function timeCell(run) {
  const { text, title } = timing(run);
  const td = cell('td', 'num', text);
  if (title) td.title = title;
  return td;
}

function cell(tag, className = '', text) {
  const c = document.createElement(tag);
  if (className) c.className = className;
  if (text !== undefined) c.textContent = text;
  return c;
}
