import assert from 'node:assert/strict';
import { test } from 'node:test';
import { curveText, lastValue, plotSummary, sci } from '../src/draw/alttext.js';

test('the text alternative of a plot gives each curve its last error and verdict', () => {
  assert.equal(lastValue([1, 2, null, NaN]), 2);
  assert.equal(lastValue([]), null);
  assert.equal(sci(1.234e-5), '1.23e-5');
  assert.equal(sci(null), 'no value');
  assert.equal(curveText([1e-3, 2e-3], { verdict: 'bounded' }), 'last error 2.00e-3, bounded');
  assert.equal(curveText([1e-3], { status: 'failed' }), 'last error 1.00e-3, failed');
  assert.equal(curveText([], { status: 'running' }), 'last error no value, running');
  assert.equal(
    plotSummary('Energy H error against t', 'Knife edge · ε = 0', [{ label: 'A', text: 'last error 1.00e-3, bounded' }, { label: 'B', text: 'last error 0, exact' }]),
    'Energy H error against t (Knife edge · ε = 0): A: last error 1.00e-3, bounded; B: last error 0, exact.',
  );
  assert.equal(plotSummary('T', '', []), 'T: no curves.');
});
