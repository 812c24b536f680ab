// The runs table: one row per run with its method's line and marker (palette.js), label,
// status, the verdict of each of its series (exact / bounded / drift, the numbers on hover),
// steps and time (`timing`); a failed run gets a second row with the server's message, so a
// failure is never silent, and so does a series that stops having values while its run goes
// on (its gap: from when and why). On a narrow screen each run is a small card (style.css).

import { timing } from '../data/timing.js';
import { INTEGRAL_NAME, runVerdicts } from '../data/verdicts.js';
import { humanLabel } from '../data/labels.js';
import { methodStyle } from '../draw/palette.js';
import { swatch } from '../draw/markers.js';

const STATUS = {
  running: 'running',
  ok: 'ok',
  failed: 'failed',
  cancelled: 'cancelled',
  interrupted: 'interrupted',
};

/** `catalog`: GET /systems, for each method's look. */
export function renderRuns(table, result, catalog) {
  table.hidden = result.runs.length === 0;
  const rows = [];
  result.runs.forEach((run, i) => {
    const tr = document.createElement('tr');
    tr.className = `run run-${run.status}`;
    tr.dataset.run = i;
    const name = cell('th');
    name.scope = 'row';
    name.append(swatch(methodStyle(catalog, run.method)), document.createTextNode(humanLabel(run.label)));
    const state = cell('td');
    const badge = document.createElement('span');
    badge.className = `badge ${run.status}`;
    badge.textContent = run.status === 'running' ? `running ${Math.floor(run.fraction * 100)}%` : STATUS[run.status] ?? run.status;
    state.append(badge);
    const steps = cell('td', 'num steps', run.steps === null ? '–' : run.steps.toLocaleString('en-US'));
    tr.append(name, state, verdictsCell(run, result.scene.integrals ?? []), steps, timeCell(run));
    rows.push(tr);
    if (run.status === 'failed') {
      const err = document.createElement('tr');
      err.className = 'run-error';
      const td = cell('td', '', run.error ?? 'failed without a message');
      td.colSpan = 5;
      err.append(td);
      rows.push(err);
    }
    for (const text of gapTexts(run)) {
      const gap = document.createElement('tr');
      gap.className = 'run-gap';
      const td = cell('td', '', text);
      td.colSpan = 5;
      gap.append(td);
      rows.push(gap);
    }
  });
  table.tBodies[0].replaceChildren(...rows);
}

/** One sentence per series of `run` with a gap, naming the series (its integral's name). */
export function gapTexts(run) {
  return Object.entries(run.gaps ?? {}).map(([integral, gap]) => `${integralName(integral)}: ${gap.message}`);
}

function verdictsCell(run, integrals) {
  const td = cell('td', 'verdicts');
  const list = cell('div', 'verdicts-list');
  td.append(list);
  for (const v of runVerdicts(run, integrals)) {
    const chip = cell('span', `verdict-chip ${v.kind}`);
    chip.dataset.integral = v.integral;
    chip.dataset.kind = v.kind;
    const gap = run.gaps?.[v.integral];
    chip.title = gap ? `${v.title}\n${gap.message}` : v.title;
    if (gap) chip.classList.add('has-gap');
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

function integralName(id) {
  return INTEGRAL_NAME[id] ?? id;
}
