import assert from 'node:assert/strict';
import { test } from 'node:test';
import { axisTicks, chartSvg, withTicks } from '../src/draw/export.js';

// A chart as uPlot's public API shows it: sizes, plotting box (in device pixels), scales
// through valToPos (CSS pixels from the box's corner), series (stroke resolved to a function)
// and data. The x scale maps 1…3 onto 0…200 px, the log y scale one decade to 40 px.
function chart() {
  return {
    width: 300,
    height: 200,
    ctx: { canvas: { width: 600 } }, // a device-pixel ratio of 2: the SVG is in CSS pixels
    bbox: { left: 100, top: 20, width: 400, height: 300 }, // 50, 10, 200, 150 in CSS pixels
    axes: [
      { scale: 'x', side: 2, label: 't' },
      { scale: 'y', side: 3, label: 'error' },
    ],
    series: [
      { label: 't' },
      { label: 'LF <1>', stroke: () => '#2563eb', width: 2, points: { filter: () => [0, 2] } },
      { label: 'hidden', stroke: () => '#000', show: false },
    ],
    data: [
      [1, 2, 3],
      [1e-3, null, 1e-1],
      [1, 1, 1],
    ],
    valToPos: (v, scale) => (scale === 'x' ? (v - 1) * 100 : -Math.log10(v) * 40),
  };
}

// What uPlot does with the axis options on a draw: every tick to `grid.filter`, the ticks
// its filter kept (null where it blanked one) to `values`.
function draw(u, opts) {
  opts.axes[0].grid.filter(u, [1, 2, 3], 0, 50, 1);
  opts.axes[0].values(u, [1, 2, 3], 0, 50, 1);
  opts.axes[1].grid.filter(u, [1e-3, 1e-2, 1e-1], 1, 30, 1);
  opts.axes[1].values(u, [1e-3, null, 1e-1], 1, 30, 1);
}

test('withTicks records the ticks uPlot draws and changes nothing it returns', () => {
  const u = chart();
  const mine = (self, splits) => splits.map((v) => (v === null ? '' : `≈${v}`));
  const opts = withTicks().opts(u, { axes: [{ values: mine, grid: { stroke: '#eee' } }, {}] });
  assert.equal(opts.axes[0].grid.stroke, '#eee', 'the axis options are kept');
  assert.deepEqual(opts.axes[0].values(u, [1, 2], 0), ['≈1', '≈2']);
  assert.deepEqual(opts.axes[0].grid.filter(u, [1, 2], 0), [1, 2]);
  draw(u, opts);
  assert.deepEqual(axisTicks(u, 0), [
    { value: 1, label: '≈1' },
    { value: 2, label: '≈2' },
    { value: 3, label: '≈3' },
  ]);
  // A tick uPlot's filter blanked keeps its grid line, without a label.
  assert.deepEqual(axisTicks(u, 1).map((t) => t.label), ['0.001', null, '0.1']);
  assert.deepEqual(axisTicks(chart(), 0), [], 'nothing before a draw');
});

test('the SVG export draws the ticks uPlot chose, the shown series and their markers', () => {
  const u = chart();
  draw(u, withTicks().opts(u, { axes: [{ values: (self, s) => s.map(String) }, {}] }));
  const svg = chartSvg(u, { title: 'Energy error', caption: 'knife edge', styles: [{ marker: 'square', colour: '#2563eb', hollow: false }, null], floor: 1e-2 });
  assert.match(svg, /^<svg xmlns="http:\/\/www.w3.org\/2000\/svg" width="324" height="\d+"/);
  assert.ok(svg.trimEnd().endsWith('</svg>'));
  for (const label of ['Energy error', 'knife edge', '1', '2', '3', '0.001', '0.1', 't', 'error', 'round-off floor', 'LF &lt;1&gt;']) {
    assert.ok(svg.includes(`>${label}</text>`), `the text ${label}`);
  }
  assert.ok(!svg.includes('hidden'), 'a hidden series is left out');
  // Grid lines across the plotting box (50…250 × 10…160 in CSS pixels) at x = 50, 150, 250
  // and at each of the three y ticks, blank or not.
  for (const x of [50, 150, 250]) assert.ok(svg.includes(`d="M${x} 10L${x} 160"`), `a grid line at x = ${x}`);
  assert.equal((svg.match(/stroke="#e2e8f0"/g) ?? []).length, 6);
  // The series: a moveTo at (1, 1e-3) then, the gap at t = 2 breaking it, a moveTo at (3, 1e-1).
  const line = svg.match(/<path d="([^"]*)" fill="none" stroke="#2563eb" stroke-width="2"/);
  assert.ok(line, 'the series line');
  assert.equal((line[1].match(/M/g) ?? []).length, 2, 'broken at the gap');
  // Two markers (filled squares) where the series' points filter puts them, one in the legend.
  assert.equal((svg.match(/<path d="[^"]*Z[^"]*Z" fill="#2563eb"/g) ?? []).length, 1);
  assert.match(svg, /<clipPath id="c\d+">/, 'the series are clipped to the plotting box');
});
