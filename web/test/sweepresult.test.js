import assert from 'node:assert/strict';
import { test } from 'node:test';
import { SweepResult, cellLines, cellState, fmt, sweepFromCSV, sweepFromJSON, writtenInPython } from '../src/map/sweepresult.js';
import { cellColor, decadeRange, KIND_COLORS, logError, tickStep, viridis } from '../src/map/heatmap.js';
import { powerOfTen } from '../src/draw/axes.js';
import { csvField, parseCSV } from '../src/data/csv.js';

const start = {
  axes: [
    { path: 'methods.alpha', values: [0.3, 0.5] },
    { path: 'params.epsilon', values: [0, 0.25, 0.5] },
  ],
  methods: [{ id: 'm', alpha: 0.5, label: 'M^0.5' }, { id: 'n', label: 'N' }],
  integrals: ['energy', 'constraint'],
  cells: 6,
  criterion: 'drift when late/early > 2',
};

const verdict = (kind, max) => ({ kind, max, early: max / 2, late: max / 3, ratio: 0.66 });

function row(cell, method_index, status = 'ok') {
  const values = [start.axes[0].values[Math.floor(cell / 3)], start.axes[1].values[cell % 3]];
  const method = method_index === 0 ? { id: 'm', alpha: values[0], label: `M^${values[0]}` } : start.methods[1];
  const { label, ...run } = method;
  return {
    cell,
    values,
    method_index,
    method,
    status,
    error: status === 'failed' ? 'step 12 at t = 1.2: Newton did not converge' : status === 'invalid' ? 'v: not tangent, "quoted"' : null,
    steps: status === 'invalid' ? 0 : 3000,
    cpu_ms: status === 'invalid' ? null : 1.5,
    newton_iterations: method_index === 0 && status !== 'invalid' ? 6012 : null,
    verdicts: status === 'ok' ? { energy: verdict(cell % 2 ? 'drift' : 'bounded', 1e-3 * (cell + 1)), constraint: verdict('exact', 0) } : {},
    gaps: cell === 0 && method_index === 0 ? { energy: { since: 72016.9, reason: 'passenger_at_rest', message: '…' } } : {},
    simulate: { system: 's', preset: 'p', params: { epsilon: values[1] }, methods: [run], points: 1000 },
  };
}

function filled(order) {
  const r = new SweepResult(start);
  for (const c of order) r.addCell({ cell: c, values: row(c, 0).values, rows: [row(c, 1, c === 4 ? 'failed' : 'ok'), row(c, 0, c === 5 ? 'invalid' : 'ok')] });
  return r;
}

test('cells arrive in any order and fill their place', () => {
  const r = new SweepResult(start);
  assert.deepEqual(r.counts, [2, 3]);
  assert.equal(r.row(4, 0), null);
  assert.deepEqual(cellState(r.row(4, 0), 'energy'), { kind: 'pending', max: null });
  r.addCell({ cell: 4, values: [0.5, 0.25], rows: [row(4, 1, 'failed'), row(4, 0)] });
  r.progress({ cells_done: 2, cells: 6, elapsed_ms: 10 });
  assert.equal(r.received, 1);
  assert.equal(r.fraction, 2 / 6, 'the larger of cells received and counted');
  assert.equal(r.row(4, 0).method.label, 'M^0.5');
  assert.equal(r.row(4, 1).status, 'failed');
  assert.deepEqual(cellState(r.row(4, 0), 'energy'), { kind: 'bounded', max: 5e-3 });
  assert.deepEqual(cellState(r.row(4, 1), 'energy'), { kind: 'failed', max: null });
  assert.deepEqual(cellState(r.row(4, 0), 'latitude'), { kind: 'none', max: null });
  // The same cell twice (a retried event) is counted once.
  r.addCell({ cell: 4, values: [0.5, 0.25], rows: [row(4, 0), row(4, 1)] });
  assert.equal(r.received, 1);
  assert.throws(() => r.addCell({ cell: 6, rows: [] }), /cell 6/);
  const full = filled([5, 0, 3, 1, 4, 2]);
  assert.equal(full.fraction, 1);
  assert.deepEqual(cellState(full.row(5, 0), 'energy'), { kind: 'invalid', max: null });
});

test('the JSON download is the JSON answer: rows by cell, then method', () => {
  const r = filled([5, 0, 3, 1, 4, 2]);
  const json = r.toJSON();
  assert.deepEqual(Object.keys(json), ['axes', 'methods', 'integrals', 'cells', 'criterion', 'rows']);
  assert.deepEqual(json.rows.map((x) => [x.cell, x.method_index]), [0, 1, 2, 3, 4, 5].flatMap((c) => [[c, 0], [c, 1]]));
  assert.deepEqual(json.axes, start.axes);
  assert.equal(json.cells, 6);
  // A partial sweep (cancelled) downloads what arrived.
  assert.deepEqual(filled([3]).toJSON().rows.map((x) => x.cell), [3, 3]);
});

test('the CSV download has the CSV answer columns, a row per run', () => {
  const csv = filled([2, 1, 0, 5, 4, 3]).toCSV();
  const lines = csv.trimEnd().split('\n');
  assert.equal(
    lines[0],
    'cell,methods.alpha,params.epsilon,method_index,method,status,error,steps,cpu_ms,newton_iterations,' +
      'energy.kind,energy.max,energy.early,energy.late,energy.ratio,energy.gap_since,' +
      'constraint.kind,constraint.max,constraint.early,constraint.late,constraint.ratio,constraint.gap_since,simulate',
  );
  assert.equal(lines.length, 1 + 12);
  assert.ok(lines[1].startsWith('0,0.3,0,0,M^0.3,ok,,3000,1.5,6012,bounded,0.001,0.0005,'), lines[1]);
  assert.match(lines[1], /,0\.66,72016\.9,exact,0,0,0,0\.66,,"/, 'the gap start after the energy verdict, empty for none');
  // Quotes in a message and the simulate body's JSON are quoted as CSV fields.
  const invalid = lines.find((l) => l.startsWith('5,') && l.includes('invalid'));
  assert.match(invalid, /,"v: not tangent, ""quoted""",0,,,/);
  assert.match(lines[1], /,"\{""system"":""s"",""preset"":""p"",.*\}"$/);
  const failed = lines.find((l) => l.includes('failed'));
  assert.match(failed, /^4,0\.5,0\.25,1,N,failed,step 12 at t = 1\.2: Newton did not converge,3000,1\.5,,,,,,,,,,,,,,/);
});

test('a tooltip names the cell, the method as run there and the numbers', () => {
  const r = filled([0, 1, 2, 3, 4, 5]);
  const lines = cellLines(r, 4, 0, 'energy');
  // Axes by the labels the form uses, the method as the rest of the page writes it.
  assert.equal(lines[0], 'α (every method) = 0.5');
  assert.equal(lines[1], 'ε (epsilon) = 0.25');
  assert.equal(lines[2], 'M⁰·⁵: ok');
  assert.equal(lines[3], 'energy: bounded');
  assert.match(lines[4], /^max 5\.00e-3 · early max 2\.50e-3 · late mean 1\.67e-3 · late\/early 0\.66$/);
  assert.equal(lines[5], '3000 steps · 1.5 ms CPU · 6012 Newton iterations');
  assert.deepEqual(cellLines(r, 4, 1, 'energy').slice(2, 4), ['N: failed', 'step 12 at t = 1.2: Newton did not converge']);
  assert.deepEqual(cellLines(new SweepResult(start), 2, 0, 'energy'), ['α (every method) = 0.3', 'ε (epsilon) = 0.5', 'not computed yet']);
  assert.equal(fmt(0.30000000000000004), '0.3');
  assert.equal(fmt(1e-7), '1.00e-7');
});

test('colours: verdicts by kind, errors on a log scale over whole decades', () => {
  assert.deepEqual(decadeRange([1e-3, 2e-9, null, 0.5]), [-9, 0]);
  assert.deepEqual(decadeRange([1e-3]), [-3, -2]);
  assert.deepEqual(decadeRange([0]), [-16, -15], 'an exact zero sits on the floor');
  assert.deepEqual(decadeRange([]), [-16, 0]);
  assert.equal(logError(0), -16);
  assert.equal(viridis(0), '#440154');
  assert.equal(viridis(1), '#fde725');
  assert.equal(viridis(2), '#fde725', 'clamped');
  assert.match(viridis(0.37), /^#[0-9a-f]{6}$/);
  assert.equal(cellColor({ kind: 'drift', max: 1 }, 'verdict', [-3, 0]), KIND_COLORS.drift);
  assert.equal(cellColor({ kind: 'drift', max: 1 }, 'log', [-3, 0]), viridis(1));
  assert.equal(cellColor({ kind: 'exact', max: 1e-3 }, 'log', [-3, 0]), viridis(0));
  // Failed, invalid and pending cells keep their own colours in both modes.
  for (const kind of ['failed', 'invalid', 'pending', 'none']) {
    assert.equal(cellColor({ kind, max: null }, 'log', [-3, 0]), KIND_COLORS[kind]);
    assert.equal(cellColor({ kind, max: null }, 'verdict', [-3, 0]), KIND_COLORS[kind]);
  }
  assert.equal(new Set(Object.values(KIND_COLORS)).size, Object.keys(KIND_COLORS).length, 'every kind has its own colour');
  assert.equal(tickStep(21, 600, 52), 2);
  assert.equal(tickStep(5, 600, 52), 1);
  assert.equal(powerOfTen(-12), '10⁻¹²');
});

test('a sweep saved as JSON opens as a finished result, and a bad file says what it lacks', () => {
  const saved = filled([0, 1, 2, 3, 4, 5]).toJSON();
  const python = { id: 'python', name: 'my LF', label: 'my LF' };
  saved.methods[1] = python;
  for (const r of saved.rows) if (r.method_index === 1) r.method = python;
  const opened = sweepFromJSON(JSON.parse(JSON.stringify(saved)));
  assert.equal(opened.received, 6);
  assert.equal(opened.fraction, 1);
  assert.deepEqual(opened.toJSON(), saved);
  assert.equal(writtenInPython(opened.row(2, 1)), true);
  assert.equal(writtenInPython(opened.row(2, 0)), false);
  assert.throws(() => sweepFromJSON([]), /expected an object/);
  assert.throws(() => sweepFromJSON({ ...saved, axes: [] }), /"axes" must list 1 to 3 axes/);
  assert.throws(() => sweepFromJSON({ ...saved, cells: 7 }), /"cells" is 7, but the axes make 6/);
  assert.throws(() => sweepFromJSON({ ...saved, rows: [{ cell: 9, method_index: 0 }] }), /rows\[0\] needs a "cell" below 6/);
  assert.throws(() => sweepFromJSON({ ...saved, rows: [{ cell: 0, method_index: -1 }] }), /"method_index" below 2/);
});

test('a sweep saved as CSV by the page opens to the rows of its JSON', () => {
  const saved = filled([3, 0, 5, 1, 4, 2]);
  const json = saved.toJSON();
  const opened = sweepFromCSV(saved.toCSV());
  assert.deepEqual(opened.axes, json.axes, 'the axes from their columns, in cell order');
  assert.deepEqual(opened.integrals, json.integrals);
  assert.equal(opened.cells, 6);
  assert.equal(opened.fraction, 1);
  // Each method as its first row ran it: a CSV does not hold the methods as listed.
  assert.deepEqual(opened.methods, [json.rows[0].method, json.rows[1].method]);
  // Every row and verdict, but a gap's reason and message.
  const sinceOnly = (r) => ({ ...r, gaps: Object.fromEntries(Object.entries(r.gaps).map(([i, g]) => [i, { since: g.since }])) });
  assert.deepEqual(opened.rows(), json.rows.map(sinceOnly));
  assert.equal(opened.criterion, '', 'no criterion in a CSV');
  assert.equal(opened.toCSV(), saved.toCSV(), 'it saves the same CSV again');
  assert.deepEqual(cellLines(opened, 4, 0, 'energy'), cellLines(saved, 4, 0, 'energy'));
});

// `POST /sweep`'s CSV answer as the server writes it (server/src/sweep/csv.rs): numbers as
// JSON writes them, nulls empty, observables, the simulate body as quoted JSON.
const SERVER_CSV = `cell,params.epsilon,step,method_index,method,status,error,steps,cpu_ms,newton_iterations,\
energy.kind,energy.max,energy.early,energy.late,energy.ratio,energy.gap_since,\
constraint.kind,constraint.max,constraint.early,constraint.late,constraint.ratio,\
constraint.gap_since,observables.x,observables.speed,simulate
0,0.0,0.02,0,DLA^0.4,ok,,15,0.8,30,bounded,0.0002,0.0001,0.0001,1.0,,exact,1e-15,1e-15,1e-15,1.0,,0.25,1.5,"{""methods"":[{""alpha"":0.4,""id"":""dla""}],""step"":0.02,""system"":""cvt""}"
1,0.0,0.01,0,DLA^0.4,ok,,30,1.2,60,drift,0.0015,0.0001,0.001,10.0,,exact,0.0,0.0,0.0,,2.5,0.5,,"{""methods"":[{""alpha"":0.4,""id"":""dla""}],""step"":0.01,""system"":""cvt""}"
2,0.5,0.02,0,DLA^0.4,failed,"step 7 at t = 0.06: diverged, ""too large""",6,,12,,,,,,,,,,,,,,,"{""methods"":[{""alpha"":0.4,""id"":""dla""}],""step"":0.02,""system"":""cvt""}"
3,0.5,0.01,0,DLA^0.4,invalid,v: the initial velocity does not satisfy the constraints,0,,,,,,,,,,,,,,,,,"{""methods"":[{""alpha"":0.4,""id"":""dla""}],""step"":0.01,""system"":""cvt""}"
`;

test("the server's CSV answer opens: axes, method, integrals, observables and verdicts", () => {
  const r = sweepFromCSV(SERVER_CSV);
  assert.deepEqual(r.axes, [{ path: 'params.epsilon', values: [0, 0.5] }, { path: 'step', values: [0.02, 0.01] }]);
  assert.deepEqual(r.methods, [{ alpha: 0.4, id: 'dla', label: 'DLA^0.4' }]);
  assert.deepEqual(r.integrals, ['energy', 'constraint']);
  assert.deepEqual(r.observables, ['x', 'speed']);
  assert.equal(r.cells, 4);
  assert.deepEqual(cellState(r.row(0, 0), 'energy'), { kind: 'bounded', max: 2e-4 });
  assert.deepEqual(cellState(r.row(1, 0), 'energy'), { kind: 'drift', max: 1.5e-3 });
  assert.deepEqual(r.row(1, 0).verdicts.constraint, { kind: 'exact', max: 0, early: 0, late: 0, ratio: null });
  assert.deepEqual(r.row(1, 0).gaps, { constraint: { since: 2.5 } });
  assert.deepEqual(r.row(1, 0).observables, { x: 0.5, speed: null });
  assert.deepEqual(cellState(r.row(2, 0), 'energy'), { kind: 'failed', max: null });
  assert.equal(r.row(2, 0).error, 'step 7 at t = 0.06: diverged, "too large"');
  assert.equal(r.row(2, 0).cpu_ms, null);
  assert.deepEqual(cellState(r.row(3, 0), 'energy'), { kind: 'invalid', max: null });
  assert.deepEqual(r.row(3, 0).simulate, { methods: [{ alpha: 0.4, id: 'dla' }], step: 0.01, system: 'cvt' });
  // Saved again by the page: the same columns, the observables' before simulate.
  assert.equal(r.toCSV().split('\n')[0], SERVER_CSV.split('\n')[0]);
  assert.deepEqual(r.toJSON().observables, ['x', 'speed']);
  // Rows in any order, line ends \r\n, a byte-order mark (a spreadsheet's save).
  const [head, ...lines] = SERVER_CSV.trimEnd().split('\n');
  const shuffled = sweepFromCSV(`\ufeff${[head, ...lines.reverse()].join('\r\n')}\r\n`);
  assert.deepEqual(shuffled.rows(), r.rows());
  // Without the simulate column (pandas' CSV of `to_pandas()`): the numbers, no run to open.
  const bare = sweepFromCSV(parseCSV(SERVER_CSV).map((f) => f.slice(0, -1).map(csvField).join(',')).join('\n'));
  assert.deepEqual(bare.methods, [{ label: 'DLA^0.4' }]);
  assert.deepEqual(cellState(bare.row(1, 0), 'energy'), cellState(r.row(1, 0), 'energy'));
  assert.equal(bare.row(1, 0).simulate, null);
});

test('a bad CSV says what it lacks', () => {
  const [head, ...lines] = SERVER_CSV.trimEnd().split('\n');
  const bad = (text, message) => assert.throws(() => sweepFromCSV(text), (e) => e.message.startsWith('this is not a sweep saved as CSV: ') && message.test(e.message), message);
  bad('', /the header must start with "cell", the axes' paths, then "method_index", "method", "status"/);
  bad(JSON.stringify(filled([0]).toJSON()), /the header must start with "cell"/);
  bad(head.replace(',step,', ',step,a,b,'), /more than 3 axes/);
  bad(head, /it has no rows/);
  bad(`${head}\n0,0.0,0.02\n`, /row 1 has 3 fields, the header 25/);
  bad([head, lines[0].replace(',15,', ',many,')].join('\n'), /row 1: "steps" is many, not a number/);
  bad([head, lines[0].replace('0,DLA', 'x,DLA')].join('\n'), /"method_index" is x, not a number/);
  bad(`${head}\n0,"unclosed`, /a quoted field is never closed/);
  bad([head, lines[0].replace('"{', '"nope{')].join('\n'), /row 1: "simulate" is not JSON/);
  // The rows of step 0.02 (cells 0 and 2) missing: the step axis is not known whole.
  bad([head, lines[1], lines[3]].join('\n'), /cell 3 is not where its axis values put it \(an axis value that no row has/);
  // A partial sweep whose rows have every axis value opens, the other cells pending.
  const r4 = sweepFromCSV(SERVER_CSV);
  const partial = sweepFromCSV([head, lines[1], lines[2]].join('\n'));
  assert.deepEqual(partial.axes, r4.axes, 'each value at its place, whichever rows came');
  assert.equal(partial.received, 2);
  assert.deepEqual(cellState(partial.row(0, 0), 'energy'), { kind: 'pending', max: null });
});
