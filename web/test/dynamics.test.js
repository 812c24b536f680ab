import assert from 'node:assert/strict';
import { test } from 'node:test';
import { defaultPicks, dynamicsSystem, finiteExtent, niceTicks, observablesFor, paddedRange, sectionFor, xyCSV, xyColumns } from '../src/data/dynamics.js';
import { Result } from '../src/data/result.js';
import { SvgContext } from '../src/draw/svgcanvas.js';
import { layout, sparse } from '../src/draw/xyplot.js';

const catalog = {
  methods: [],
  systems: [
    { id: 'cvt_pendulum', general: { coordinates: ['x1', 'x2', 'zeta'] }, formulas: { passenger: ['x1', 'x2'], driver: 'zeta' } },
    { id: 'chaotic_oscillator', general: { coordinates: ['x', 'y', 'z'] }, formulas: null },
  ],
};

test('the paper’s form picks the passenger plane and the driver’s turns', () => {
  const sys = dynamicsSystem(catalog, 'cvt_pendulum');
  assert.deepEqual(sys.quantities, ['x1', 'x2', 'zeta', 'x1_dot', 'x2_dot', 'zeta_dot']);
  assert.deepEqual(sys.defaults.trajectory, { x: 'x1', y: 'x2' });
  assert.deepEqual(sys.defaults.section, { surface: 'sin(zeta/2)', direction: 'both', x: 'x1', y: 'x2' });
  assert.equal(sys.key, 'cvt_pendulum:x1,x2,zeta');
});

test('other systems: the first two coordinates, the second’s phase plane at the first’s zero', () => {
  const sys = dynamicsSystem(catalog, 'chaotic_oscillator');
  assert.deepEqual(sys.defaults.trajectory, { x: 'x', y: 'y' });
  assert.deepEqual(sys.defaults.section, { surface: 'x', direction: 'up', x: 'y', y: 'y_dot' });
  assert.deepEqual(defaultPicks(['q']).trajectory, { x: 'q', y: 'q_dot' });
});

test('a custom system’s own coordinates, in either form', () => {
  const paper = dynamicsSystem(catalog, { name: 's', passenger: ['u', 'v'], driver: 'th', parameters: {}, constraints: [] });
  assert.deepEqual(paper.quantities.slice(0, 3), ['u', 'v', 'th']);
  assert.equal(paper.defaults.section.surface, 'sin(th/2)');
  const general = dynamicsSystem(catalog, { coordinates: ['a', 'b'], parameters: {}, potential: '0', constraints: [] });
  assert.deepEqual(general.defaults.section, { surface: 'a', direction: 'up', x: 'b', y: 'b_dot' });
  assert.notEqual(paper.key, general.key);
});

test('observables: every quantity by its bare name, or only the picks past the limit', () => {
  assert.deepEqual(observablesFor(['x', 'x_dot'], ['t', 'x']), { x: 'x', x_dot: 'x_dot' });
  const many = Array.from({ length: 20 }, (_, i) => `q${i}`);
  assert.deepEqual(observablesFor(many, ['t', 'q3']), { q3: 'q3' });
  assert.deepEqual(sectionFor({ surface: ' x ', direction: 'up', x: 'y', y: 'y_dot' }), { surface: 'x', direction: 'up', plot: ['y', 'y_dot'] });
  assert.deepEqual(sectionFor({ surface: 'x', direction: 'both', x: 'y', y: 'y' }).plot, ['y']);
});

test('observables and section events grow a run’s columns; the JSON and CSV carry them', () => {
  const r = new Result({ methods: [{ id: 'leapfrog', label: 'LF' }], integrals: [] }, () => 0);
  r.addObservables({ run: 0, t: [0, 1], x: [1, 2], y: [3, 4] });
  r.addObservables({ run: 0, t: [2], x: [5], y: [6] });
  r.addSection({ run: 0, t: [0.5], y: [7], y_dot: [8] });
  assert.deepEqual(r.runs[0].observables, { t: [0, 1, 2], x: [1, 2, 5], y: [3, 4, 6] });
  assert.deepEqual(xyColumns(r.runs[0], 'observables', 't', 'y'), { xs: [0, 1, 2], ys: [3, 4, 6] });
  assert.equal(xyColumns(r.runs[0], 'section', 'x', 'y'), null);
  assert.deepEqual(r.toJSON().runs[0].section, { t: [0.5], y: [7], y_dot: [8] });
  assert.equal(xyCSV(r.runs, 'section', 'y', 'y_dot'), 'run,method,status,t,y,y_dot\n0,LF,running,0.5,7,8\n');
  assert.equal(xyCSV(r.runs, 'observables', 't', 'x'), 'run,method,status,t,x\n0,LF,running,0,1\n0,LF,running,1,2\n0,LF,running,2,5\n');
});

test('ranges and ticks: padded, round, never −0', () => {
  assert.deepEqual(finiteExtent([[1, NaN, -2], [null, 3]]), [-2, 3]);
  assert.equal(finiteExtent([[]]), null);
  assert.deepEqual(paddedRange([0, 10], 0.1), [-1, 11]);
  assert.deepEqual(paddedRange([2, 2]), [1.8, 2.2]);
  assert.deepEqual(paddedRange(null), [-1, 1]);
  assert.deepEqual(niceTicks(-0.04, 1.04, 5), [0, 0.2, 0.4, 0.6, 0.8, 1]);
  assert.deepEqual(niceTicks(-1.3, 1.3, 4), [-1, -0.5, 0, 0.5, 1]);
  assert.ok(niceTicks(-1, 1, 4).every((v) => !Object.is(v, -0)));
  assert.deepEqual(niceTicks(1, 1), []);
  const L = layout([{ xs: [0, 1], ys: [5, 6] }], 400);
  assert.ok(L.xr[0] < 0 && L.xr[1] > 1 && L.xt.length >= 2 && L.box.width < 400);
});

test('sparse markers: a dozen, staggered between series', () => {
  const a = sparse(1000, 0, 5);
  const b = sparse(1000, 1, 5);
  assert.equal(a.length, 12);
  assert.ok(a.every((v, k) => v < b[k]));
  assert.deepEqual(sparse(0, 0, 1), []);
  assert.ok(sparse(3, 0, 1).every((v) => v < 3));
});

test('the SVG context draws circle markers and dashed strokes', () => {
  const ctx = new SvgContext(10, 10);
  ctx.beginPath();
  ctx.arc(5, 5, 2);
  ctx.closePath();
  ctx.setLineDash([4, 2]);
  ctx.stroke();
  assert.match(ctx.toString(), /<path d="M7 5A2 2 0 1 0 3 5A2 2 0 1 0 7 5Z" fill="none" stroke="#000" stroke-width="1" stroke-dasharray="4 2"\/>/);
});
