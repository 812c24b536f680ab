// A sweep as it streams in: the `start` event's axes, methods and integrals, then each cell's
// rows as its `cell` event arrives (in any order), the progress and the closing counts; or
// one saved as JSON or CSV, opened from a file (`sweepFromJSON`, `sweepFromCSV`). What
// the map draws of a cell for a method and integral, the lines its tooltip shows, and the
// downloads: JSON in the shape of `POST /sweep`'s JSON answer (the rows ordered by cell,
// then method) and CSV with the columns of its CSV answer. Pure, so node tests cover it.

import { csvField, parseCSV } from '../data/csv.js';
import { sci } from '../data/verdicts.js';
import { fieldLabel, humanLabel } from '../data/labels.js';

export class SweepResult {
  constructor(start) {
    this.axes = start.axes ?? [];
    this.methods = start.methods ?? [];
    this.integrals = start.integrals ?? [];
    this.observables = start.observables ?? []; // taken at t_end, by name
    this.cells = start.cells ?? 0;
    this.criterion = start.criterion ?? '';
    this.counts = this.axes.map((a) => a.values.length);
    this.byCell = new Array(this.cells).fill(null); // rows of each cell, by method_index
    this.received = 0;
    this.reported = 0; // cells_done of the last progress event
    this.done = null;
  }

  /** Stores a `cell` event's rows (a cell sent twice replaces its rows). */
  addCell(ev) {
    const c = ev.cell;
    if (!Number.isInteger(c) || c < 0 || c >= this.cells) {
      throw new Error(`the server sent cell ${c}, but the sweep has ${this.cells} cells`);
    }
    if (this.byCell[c] === null) this.received++;
    const rows = [];
    for (const row of ev.rows ?? []) rows[row.method_index] = row;
    this.byCell[c] = rows;
  }

  /** Applies a `progress` event. */
  progress(ev) {
    if (Number.isFinite(ev.cells_done)) this.reported = ev.cells_done;
  }

  /** Applies the `done` event. */
  finish(ev) {
    this.done = ev;
  }

  /** Cells done so far in [0, 1]: the larger of those received and those the server counted. */
  get fraction() {
    return this.cells ? Math.min(1, Math.max(this.received, this.reported) / this.cells) : 0;
  }

  /** The row of a cell for a method, or null while the cell has not arrived. */
  row(cell, method) {
    return this.byCell[cell]?.[method] ?? null;
  }

  /** Every row received, ordered by cell, then method_index. */
  rows() {
    return this.byCell.flatMap((rows) => (rows ? rows.filter(Boolean) : []));
  }

  /** The JSON answer's shape: axes, methods, integrals, observables (if any), cells,
   *  criterion, rows. */
  toJSON() {
    const observables = this.observables.length ? { observables: this.observables } : {};
    return { axes: this.axes, methods: this.methods, integrals: this.integrals, ...observables, cells: this.cells, criterion: this.criterion, rows: this.rows() };
  }

  /** The CSV answer's columns: cell, one per axis, the run's, six per integral (the verdict's
   *  five and the gap's start), one per observable, simulate. */
  toCSV() {
    const head = ['cell', ...this.axes.map((a) => a.path), ...RUN_COLUMNS];
    for (const i of this.integrals) head.push(...VERDICT_FIELDS.map((f) => `${i}.${f}`), `${i}.gap_since`);
    head.push(...this.observables.map((o) => `observables.${o}`), 'simulate');
    const lines = [head.map(csvField).join(',')];
    for (const r of this.rows()) {
      const fields = [r.cell, ...this.axes.map((_, k) => r.values?.[k]), r.method_index, r.method?.label ?? r.method?.id, r.status, r.error, r.steps, r.cpu_ms, r.newton_iterations];
      for (const i of this.integrals) fields.push(...VERDICT_FIELDS.map((f) => r.verdicts?.[i]?.[f]), r.gaps?.[i]?.since);
      fields.push(...this.observables.map((o) => r.observables?.[o]), r.simulate ? JSON.stringify(r.simulate) : null);
      lines.push(fields.map((v) => csvField(v === null || v === undefined ? '' : String(v))).join(','));
    }
    return lines.join('\n') + '\n';
  }
}

const VERDICT_FIELDS = ['kind', 'max', 'early', 'late', 'ratio'];
// The columns between the axes' and the integrals'.
const RUN_COLUMNS = ['method_index', 'method', 'status', 'error', 'steps', 'cpu_ms', 'newton_iterations'];

/**
 * What a cell shows for a method and integral: `pending` (not arrived), `failed`, `invalid`,
 * `none` (it ran but the series has no verdict) or the verdict's kind; with its largest error.
 */
export function cellState(row, integral) {
  if (!row) return { kind: 'pending', max: null };
  if (row.status === 'failed' || row.status === 'invalid') return { kind: row.status, max: null };
  const v = row.verdicts?.[integral];
  return v ? { kind: v.kind, max: v.max ?? null } : { kind: 'none', max: null };
}

/** The tooltip of a cell: its axis values, the method, status and the numbers behind it. */
export function cellLines(result, cell, method, integral) {
  const row = result.row(cell, method);
  const values = row?.values ?? result.axes.map((a, k) => a.values[cellIndex(result, cell, k)]);
  const lines = result.axes.map((a, k) => `${fieldLabel(a.path)} = ${fmt(values[k])}`);
  if (!row) return [...lines, 'not computed yet'];
  lines.push(`${humanLabel(row.method?.label ?? row.method?.id ?? `method ${method}`)}: ${row.status}`);
  if (row.error) lines.push(row.error);
  const v = row.verdicts?.[integral];
  if (v) {
    const ratio = v.ratio === null || v.ratio === undefined ? '∞' : Number(v.ratio).toFixed(2);
    lines.push(`${integral}: ${v.kind}`, `max ${sci(v.max)} · early max ${sci(v.early)} · late mean ${sci(v.late)} · late/early ${ratio}`);
  } else if (row.status === 'ok') lines.push(`${integral}: no verdict (no data)`);
  const work = [row.steps !== null && row.steps !== undefined ? `${row.steps} steps` : '', Number.isFinite(row.cpu_ms) ? `${fmt(row.cpu_ms)} ms CPU` : '', Number.isFinite(row.newton_iterations) ? `${row.newton_iterations} Newton iterations` : ''].filter(Boolean);
  if (work.length) lines.push(work.join(' · '));
  return lines;
}

// A cell's index along axis k (the last axis fastest).
function cellIndex(result, cell, k) {
  let rest = cell;
  for (let a = result.counts.length - 1; a > k; a--) rest = Math.floor(rest / result.counts[a]);
  return rest % result.counts[k];
}

/** A number for a label: three significant digits, exponent form when very small or large. */
export function fmt(v) {
  if (v === null || v === undefined || !Number.isFinite(v)) return String(v ?? '–');
  const a = Math.abs(v);
  return a !== 0 && (a < 1e-3 || a >= 1e5) ? v.toExponential(2) : String(Number(v.toPrecision(3)));
}

/**
 * A sweep saved as JSON (the page's JSON download, `POST /sweep`'s JSON answer, or
 * `SweepRows.to_json()` in Python, which may hold methods written in Python) as a finished
 * result; throws an Error that says what the file lacks.
 */
export function sweepFromJSON(data) {
  const fail = (what) => {
    throw new Error(`this is not a sweep saved as JSON: ${what}`);
  };
  if (!data || typeof data !== 'object' || Array.isArray(data)) fail('expected an object');
  const axes = data.axes;
  if (!Array.isArray(axes) || !axes.length || axes.length > 3) fail('"axes" must list 1 to 3 axes');
  for (const [k, a] of axes.entries()) {
    if (typeof a?.path !== 'string' || !Array.isArray(a.values) || !a.values.length || !a.values.every(Number.isFinite)) {
      fail(`axes[${k}] needs a "path" and a non-empty list of numbers "values"`);
    }
  }
  if (!Array.isArray(data.methods) || !data.methods.length) fail('"methods" must be a non-empty list');
  if (!Array.isArray(data.integrals)) fail('"integrals" must be a list');
  if (!Array.isArray(data.rows)) fail('"rows" must be a list');
  const cells = axes.reduce((n, a) => n * a.values.length, 1);
  if (data.cells !== undefined && data.cells !== cells) fail(`"cells" is ${data.cells}, but the axes make ${cells}`);
  for (const [i, row] of data.rows.entries()) {
    const m = row?.method_index;
    if (!Number.isInteger(row?.cell) || row.cell < 0 || row.cell >= cells || !Number.isInteger(m) || m < 0 || m >= data.methods.length) {
      fail(`rows[${i}] needs a "cell" below ${cells} and a "method_index" below ${data.methods.length}`);
    }
  }
  return finished({ ...data, cells }, data.rows);
}

/**
 * A sweep saved as CSV (the page's CSV download, `POST /sweep`'s CSV answer, or `nhlab sweep
 * --merge … --format csv`) as a finished result; throws an Error that says what the file
 * lacks. A CSV has no head, so it is rebuilt from the rows: each axis from its column, each
 * value at the place its rows' cells give it (a value that no row has is not known), each
 * method from its first row (its label and the method of the row's `simulate` body), the
 * integrals from the `<integral>.kind` columns; the criterion and a gap's reason are not in
 * a CSV. Without the `simulate` column (pandas' `to_csv(index=False)` of
 * `SweepRows.to_pandas()`) the cells show their numbers but do not open in Explore.
 */
export function sweepFromCSV(text) {
  const fail = (what) => {
    throw new Error(`this is not a sweep saved as CSV: ${what}`);
  };
  let lines;
  try {
    lines = parseCSV(String(text));
  } catch (e) {
    fail(e.message);
  }
  const [head = [], ...records] = lines;
  const at = head.indexOf('method_index');
  if (head[0] !== 'cell' || at < 2 || RUN_COLUMNS.some((c, k) => head[at + k] !== c)) {
    fail(`the header must start with "cell", the axes' paths, then ${RUN_COLUMNS.map((c) => `"${c}"`).join(', ')}`);
  }
  const paths = head.slice(1, at);
  if (paths.length > 3) fail('it has more than 3 axes');
  const integrals = head.filter((h) => h.endsWith('.kind') && !h.startsWith('observables.')).map((h) => h.slice(0, -'.kind'.length));
  const observables = head.filter((h) => h.startsWith('observables.')).map((h) => h.slice('observables.'.length));
  if (!records.length) fail('it has no rows');
  const column = new Map(head.map((h, k) => [h, k]));
  const rows = records.map((fields, k) => {
    const where = `row ${k + 1}`;
    if (fields.length !== head.length) fail(`${where} has ${fields.length} fields, the header ${head.length}`);
    const field = (name) => fields[column.get(name)] ?? '';
    const number = (name) => {
      const s = field(name);
      const x = s === '' ? null : Number(s);
      if (Number.isNaN(x)) fail(`${where}: "${name}" is ${s}, not a number`);
      return x;
    };
    const row = { cell: number('cell'), values: paths.map(number), method_index: number('method_index') };
    if (!Number.isInteger(row.cell) || row.cell < 0 || !Number.isInteger(row.method_index) || row.method_index < 0) {
      fail(`${where} needs a whole "cell" and "method_index"`);
    }
    if (!row.values.every(Number.isFinite)) fail(`${where} needs a number in every axis column`);
    let simulate = null;
    try {
      simulate = field('simulate') ? JSON.parse(field('simulate')) : null;
    } catch {
      fail(`${where}: "simulate" is not JSON`);
    }
    const run = simulate?.methods?.length === 1 ? simulate.methods[0] : {};
    Object.assign(row, { method: { ...run, label: field('method') }, status: field('status'), error: field('error') || null });
    for (const c of ['steps', 'cpu_ms', 'newton_iterations']) row[c] = number(c);
    row.verdicts = {};
    row.gaps = {};
    for (const i of integrals) {
      if (field(`${i}.kind`)) row.verdicts[i] = { kind: field(`${i}.kind`), ...Object.fromEntries(VERDICT_FIELDS.slice(1).map((f) => [f, number(`${i}.${f}`)])) };
      if (field(`${i}.gap_since`)) row.gaps[i] = { since: number(`${i}.gap_since`) };
    }
    if (observables.length) row.observables = Object.fromEntries(observables.map((o) => [o, number(`observables.${o}`)]));
    row.simulate = simulate;
    return row;
  });
  rows.sort((a, b) => a.cell - b.cell || a.method_index - b.method_index);
  // Each axis has as many values as its column, each at the place its rows' cells give it
  // (the last axis fastest); then each row's values must give its cell.
  const counts = paths.map((_, k) => new Set(rows.map((r) => r.values[k])).size);
  const axes = paths.map((path, k) => {
    const stride = counts.slice(k + 1).reduce((n, c) => n * c, 1);
    const values = new Array(counts[k]);
    for (const r of rows) values[Math.floor(r.cell / stride) % counts[k]] ??= r.values[k];
    return { path, values };
  });
  for (const r of rows) {
    const cell = axes.reduce((c, a, j) => c * a.values.length + a.values.indexOf(r.values[j]), 0);
    if (cell !== r.cell) fail(`cell ${r.cell} is not where its axis values put it (an axis value that no row has, or one given twice)`);
  }
  const methods = [];
  for (const r of rows) methods[r.method_index] ??= r.method;
  const missing = methods.findIndex((m) => !m);
  if (missing >= 0) fail(`no row has method_index ${missing}`);
  const cells = axes.reduce((n, a) => n * a.values.length, 1);
  return finished({ axes, methods, integrals, observables, cells, criterion: '' }, rows);
}

// The finished result of a saved sweep's head and checked rows.
function finished(head, rows) {
  const result = new SweepResult(head);
  const byCell = new Map();
  for (const row of rows) {
    if (!byCell.has(row.cell)) byCell.set(row.cell, []);
    byCell.get(row.cell).push(row);
  }
  for (const [cell, cellRows] of byCell) result.addCell({ cell, rows: cellRows });
  result.finish({ rows: rows.length, opened: true });
  return result;
}

/** Whether a row's method was written in Python: it runs only in the Python package. */
export function writtenInPython(row) {
  return row?.method?.id === 'python';
}
