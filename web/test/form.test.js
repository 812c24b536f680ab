import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { defaultState, requestBody } from '../src/data/state.js';
import { rowMethod } from '../src/explore/form.js';

// GET /systems as the server answers it.
const catalog = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));

// A method row of the form as rowMethod reads it: its checkbox, parameter inputs and selects,
// found by the selectors the form gives them (no DOM in node).
function row({ id, params = {}, tableau, constraint, composition }) {
  const controls = {
    '.method-on': { checked: true, dataset: { id } },
    'select[data-tableau]': tableau === undefined ? null : { value: tableau },
    'select[data-constraint]': constraint === undefined ? null : { value: constraint },
    'select[data-composition]': composition === undefined ? null : { value: composition },
  };
  const inputs = Object.entries(params).map(([param, value]) => ({ dataset: { param }, value: String(value) }));
  return {
    dataset: { path: 'methods[0]' },
    querySelector: (selector) => controls[selector] ?? null,
    querySelectorAll: (selector) => (selector === 'input[data-param]' ? inputs : []),
  };
}

const number = (input) => (input.value.trim() === '' ? null : Number(input.value));

test('the form sends a PRK method with the tableau and constraint its selects hold', () => {
  const prk = rowMethod(row({ id: 'prk', tableau: 'gauss3', constraint: 'midpoint', composition: '' }), number);
  assert.deepEqual(prk, { id: 'prk', params: {}, tableau: 'gauss3', constraint: 'midpoint' });
  const composed = rowMethod(row({ id: 'prk', tableau: 'lobatto3', constraint: 'stage', composition: 'p4s3' }), number);
  assert.deepEqual(composed, { id: 'prk', params: {}, tableau: 'lobatto3', constraint: 'stage', composition: 'p4s3' });
  // Other methods carry no tableau.
  const dla = rowMethod(row({ id: 'dla', params: { alpha: 0.4 }, composition: '' }), number);
  assert.deepEqual(dla, { id: 'dla', params: { alpha: 0.4 } });
  const state = { ...defaultState(catalog, 'knife_edge', 'paper'), methods: [prk, composed, dla] };
  assert.deepEqual(requestBody(state, catalog).methods, [
    { id: 'prk', tableau: 'gauss3', constraint: 'midpoint' },
    { id: 'prk', tableau: 'lobatto3', constraint: 'stage', composition: 'p4s3' },
    { id: 'dla', alpha: 0.4 },
  ]);
});
