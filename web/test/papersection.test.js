import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { sectionRequest, verdictSentence } from '../src/paper/section.js';

const catalog = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));

test('the section figure asks the catalog’s scene, methods and section, without labels', () => {
  const body = sectionRequest(catalog);
  const f = catalog.paper_section;
  assert.equal(body.system, f.system);
  assert.equal(body.preset, f.preset);
  assert.deepEqual(body.section, f.section);
  assert.equal(body.methods.length, f.methods.length);
  assert.ok(body.methods.every((m) => m.id && !('label' in m)));
  // The reference is among them: the instrument of the catalog.
  const instruments = catalog.methods.filter((m) => m.instrument).map((m) => m.id);
  assert.ok(body.methods.some((m) => instruments.includes(m.id)));
});

test('the caption says each method’s verdicts, not the instrument’s', () => {
  const [a, b] = catalog.paper_section.integrals;
  const ref = catalog.methods.find((m) => m.instrument).id;
  const runs = [
    { label: 'LF', method: { id: 'x' }, status: 'ok', verdicts: { [a]: { kind: 'drift' }, [b]: { kind: 'bounded' } } },
    { label: 'R', method: { id: ref }, status: 'ok', verdicts: { [a]: { kind: 'exact' } } },
    { label: 'M', method: { id: 'y' }, status: 'failed', error: 'diverged' },
  ];
  const text = verdictSentence(catalog, runs);
  assert.match(text, new RegExp(`LF: ${a.replace('_', ' ')} drift, ${b.replace('_', ' ')} bounded`));
  assert.doesNotMatch(text, /R:/);
  assert.match(text, /M failed \(diverged\)/);
  assert.equal(verdictSentence(catalog, []), '');
});
