import assert from 'node:assert/strict';
import { readdirSync, readFileSync } from 'node:fs';
import { test } from 'node:test';

// The page's modules import each other without a circle: a cycle makes the order in which
// module bodies run depend on which module is loaded first.
test('the page modules import each other without a cycle', () => {
  const dir = new URL('../src/', import.meta.url);
  const files = readdirSync(dir).filter((f) => f.endsWith('.js'));
  const edges = new Map(
    files.map((f) => {
      const text = readFileSync(new URL(f, dir), 'utf8');
      return [f, [...text.matchAll(/^\s*(?:import|export)\b[^;]*?from\s+'\.\/([\w-]+\.js)'/gms)].map((m) => m[1])];
    }),
  );
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
  assert.ok(edges.get('main.js').length > 5, 'imports were found');
});
