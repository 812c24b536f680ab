import assert from 'node:assert/strict';
import { readdirSync, readFileSync } from 'node:fs';
import { dirname, join, normalize } from 'node:path';
import { test } from 'node:test';
import { fileURLToPath } from 'node:url';

// The page's modules and whom each imports (paths relative to src/).
const src = fileURLToPath(new URL('../src/', import.meta.url));
const files = readdirSync(src, { recursive: true }).filter((f) => f.endsWith('.js'));
const edges = new Map(
  files.map((f) => {
    const text = readFileSync(join(src, f), 'utf8');
    const specs = [...text.matchAll(/^\s*(?:import|export)\b[^;]*?from\s+'(\.{1,2}\/[\w./-]+\.js)'/gms)].map((m) => m[1]);
    return [f, specs.map((s) => normalize(join(dirname(f), s)))];
  }),
);

// The page's layers, each importing only from those before it: what the page knows (`data/`),
// what every view draws with (`draw/`), the views (one folder each, none importing another),
// and `main.js`, which shows one view at a time.
const LAYERS = ['data', 'draw', 'view', 'main'];
const layer = (f) => (f === 'main.js' ? 'main' : ['data', 'draw'].includes(f.split('/')[0]) ? f.split('/')[0] : 'view');

test('the page modules import each other without a cycle', () => {
  const state = new Map();
  const stack = [];
  const visit = (f) => {
    if (state.get(f) === 'done') return;
    if (state.get(f) === 'open') assert.fail(`import cycle: ${[...stack.slice(stack.indexOf(f)), f].join(' → ')}`);
    state.set(f, 'open');
    stack.push(f);
    for (const g of edges.get(f) ?? []) visit(g);
    stack.pop();
    state.set(f, 'done');
  };
  for (const f of files) visit(f);
  assert.ok(edges.get('main.js').length >= 5, 'imports were found');
});

test('every import resolves to a module of the page', () => {
  for (const [f, targets] of edges) for (const t of targets) assert.ok(edges.has(t), `${f} imports ${t}, which does not exist`);
});

test('the layers import downwards only, and no view imports another', () => {
  for (const [f, targets] of edges) {
    for (const t of targets) {
      const [from, to] = [layer(f), layer(t)];
      assert.ok(LAYERS.indexOf(to) <= LAYERS.indexOf(from), `${f} (${from}) imports ${t} (${to})`);
      if (from === 'view' && to === 'view') assert.equal(f.split('/')[0], t.split('/')[0], `${f} imports another view's ${t}`);
    }
  }
  // Each view is a folder with its `view.js`.
  for (const v of ['explore', 'scorecard', 'paper', 'workprecision', 'map']) assert.ok(edges.has(`${v}/view.js`), `${v}/view.js`);
});
