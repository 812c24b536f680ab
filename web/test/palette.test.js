import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { MARKERS, addMarker, methodStyle } from '../src/draw/palette.js';
import { SvgContext } from '../src/draw/svgcanvas.js';
import { humanLabel } from '../src/data/labels.js';
import { runVerdicts } from '../src/data/verdicts.js';

// GET /systems as the server answers it, with compositions as the server lists them.
const fixture = JSON.parse(readFileSync(new URL('./fixtures/systems.json', import.meta.url), 'utf8'));
const catalog = { ...fixture, compositions: fixture.compositions ?? [{ id: 'c3' }, { id: 'c5' }] };
const [first, second, third] = catalog.methods;
const withParam = catalog.methods.find((m) => m.params.length);
const param = withParam.params[0];

test('a method keeps its colour and marker whatever the run list', () => {
  const listA = [first, second, third].map((m) => ({ id: m.id, label: m.id }));
  const listB = [third, { id: first.id }].map((m) => ({ id: m.id, label: m.id }));
  const a = listA.map((m) => methodStyle(catalog, m));
  const b = listB.map((m) => methodStyle(catalog, m));
  assert.deepEqual(b[0], a[2]);
  assert.deepEqual(b[1], a[0]);
  // Different catalog methods: different colours and markers.
  assert.equal(new Set(catalog.methods.map((m) => methodStyle(catalog, { id: m.id }).colour)).size, catalog.methods.length);
  assert.equal(new Set(catalog.methods.map((m) => methodStyle(catalog, { id: m.id }).marker)).size, catalog.methods.length);
  assert.deepEqual(methodStyle(catalog, { id: first.id }), { colour: methodStyle(catalog, { id: first.id }).colour, dash: null, marker: MARKERS[0], hollow: false });
});

test('past ten methods, colours come round with another marker: no two share both', () => {
  const many = { methods: Array.from({ length: 25 }, (_, i) => ({ id: `m${i}`, params: [] })) };
  const looks = many.methods.map((m) => methodStyle(many, { id: m.id }));
  assert.equal(new Set(looks.map((s) => `${s.colour} ${s.marker}`)).size, looks.length);
  assert.equal(looks[10].colour, looks[0].colour);
  assert.notEqual(looks[10].marker, looks[0].marker);
});

test('a run, a run method and a form method of the same method look the same', () => {
  const inline = { id: withParam.id, [param.name]: param.default, label: 'x' };
  const form = { id: withParam.id, params: { [param.name]: param.default } };
  assert.deepEqual(methodStyle(catalog, { method: inline }), methodStyle(catalog, inline));
  assert.deepEqual(methodStyle(catalog, form), methodStyle(catalog, inline));
  assert.equal(methodStyle(catalog, form).hollow, false);
});

test('a parameter off its default shades the colour, hollow, and stays stable', () => {
  const base = methodStyle(catalog, { id: withParam.id });
  const span = param.max - param.min;
  const lower = methodStyle(catalog, { id: withParam.id, [param.name]: param.default - span / 10 });
  const higher = methodStyle(catalog, { id: withParam.id, params: { [param.name]: param.default + span / 10 } });
  assert.notEqual(lower.colour, base.colour);
  assert.notEqual(higher.colour, base.colour);
  assert.notEqual(lower.colour, higher.colour);
  assert.equal(lower.marker, base.marker);
  assert.equal(lower.hollow, true);
  assert.deepEqual(methodStyle(catalog, { id: withParam.id, [param.name]: param.default - span / 10 }), lower);
  // Darker below the default, lighter above (by the sum of the channels).
  const sum = (hex) => [1, 3, 5].reduce((a, i) => a + parseInt(hex.slice(i, i + 2), 16), 0);
  assert.ok(sum(lower.colour) < sum(base.colour));
  assert.ok(sum(higher.colour) > sum(base.colour));
  // An empty or unknown parameter value is the default.
  assert.deepEqual(methodStyle(catalog, { id: withParam.id, params: { [param.name]: NaN } }), base);
});

test('a composed method keeps its base colour and marker, with a dash of its composition', () => {
  const base = methodStyle(catalog, { id: second.id });
  const c0 = methodStyle(catalog, { id: second.id, composition: catalog.compositions[0].id });
  const c1 = methodStyle(catalog, { id: second.id, composition: catalog.compositions[1].id });
  assert.equal(c0.colour, base.colour);
  assert.equal(c0.marker, base.marker);
  assert.ok(Array.isArray(c0.dash) && c0.dash.length >= 2);
  assert.notDeepEqual(c0.dash, c1.dash);
  assert.equal(base.dash, null);
});

test('a method missing from the catalog still gets a stable look', () => {
  const a = methodStyle(catalog, { id: 'not-in-the-catalog' });
  assert.deepEqual(methodStyle(catalog, { id: 'not-in-the-catalog' }), a);
  assert.match(a.colour, /^#[0-9a-f]{6}$/);
  assert.ok(MARKERS.includes(a.marker));
  assert.match(methodStyle(null, { id: first.id }).colour, /^#[0-9a-f]{6}$/);
});

test('every marker draws a closed outline or strokes', () => {
  for (const m of MARKERS) {
    const ctx = new SvgContext(20, 20);
    ctx.beginPath();
    addMarker(ctx, m, 10, 10, 4);
    ctx.stroke();
    assert.match(ctx.toString(), /<path d="M[\d.]+ [\d.]+/, m);
  }
});

test('labels for people: exponents as superscripts, verdict titles with the rendered label', () => {
  assert.equal(humanLabel('A^{0,1}'), 'A⁰˒¹');
  assert.equal(humanLabel('A^0.4'), 'A⁰·⁴');
  assert.equal(humanLabel('B∘c3'), 'B∘c3');
  const [v] = runVerdicts({ label: 'A^{0,1}', status: 'ok', verdicts: { energy: { kind: 'bounded', max: 1e-3, early: 1e-3, late: 1e-3, ratio: 1 } } }, ['energy']);
  assert.match(v.title, /^A⁰˒¹, energy: bounded: max 1\.00e-3/);
});

test('an instrument (the reference) is grey, with a marker of its own', () => {
  const ref = catalog.methods.find((m) => m.instrument);
  assert.ok(ref, 'the catalog lists the reference as an instrument');
  const look = methodStyle(catalog, { id: ref.id, label: 'reference' });
  assert.equal(look.colour, '#94a3b8');
  const others = catalog.methods.filter((m) => !m.instrument).map((m) => methodStyle(catalog, { id: m.id }));
  assert.ok(others.every((o) => o.colour !== look.colour && o.marker !== look.marker));
});
