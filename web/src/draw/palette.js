// Each method's look, the same in every plot and table whatever the run's method list: a
// colour and a marker shape from the method's place in the catalog's `methods` (GET
// /systems, a fixed order); a method with parameters other than its defaults takes a darker
// or lighter shade of its colour (by how far the parameter moves) and a hollow marker; a
// composed method keeps its base's colour and marker with a dash of its own (by the
// composition's place in the catalog's `compositions`); an instrument (the reference) is
// grey. `methodStyle` is pure (node tests
// cover it); the rest draws it: uPlot series options, the markers on a canvas, and SVG
// swatches for legends and tables.

const COLOURS = ['#2563eb', '#dc2626', '#16a34a', '#9333ea', '#ea580c', '#0891b2', '#ca8a04', '#db2777', '#475569', '#65a30d'];
export const MARKERS = ['circle', 'square', 'triangle', 'diamond', 'triangle-down', 'cross', 'star', 'plus', 'pentagon', 'hexagon'];
const DASHES = [[10, 4], [3, 3], [12, 4, 3, 4], [6, 3, 1, 3], [2, 5], [16, 6]];
const NOT_PARAMS = new Set(['id', 'label', 'composition', 'params']);
// The colour of an instrument (the reference solve run as a method): grey, whatever its place.
const INSTRUMENT = '#94a3b8';

function hash(text) {
  let h = 0;
  for (const c of String(text)) h = (h * 31 + c.codePointAt(0)) >>> 0;
  return h;
}

/** A method's parameters, from a run's method (`{id, alpha, …}`) or a form's (`{id, params}`). */
function paramsOf(method) {
  const own = Object.fromEntries(Object.entries(method).filter(([k, v]) => !NOT_PARAMS.has(k) && typeof v === 'number'));
  return { ...own, ...(method.params ?? {}) };
}

// Mixes a #rrggbb colour toward black (t < 0) or white (t > 0) by |t|.
function shade(hex, t) {
  const target = t < 0 ? 0 : 255;
  const a = Math.abs(t);
  const c = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16)).map((v) => Math.round(v + (target - v) * a));
  return `#${c.map((v) => v.toString(16).padStart(2, '0')).join('')}`;
}

// How far a method's parameters sit from their defaults, signed, 0 at the defaults: the
// first parameter that differs, as a fraction of its range.
function offset(info, params) {
  for (const p of info?.params ?? []) {
    const v = params[p.name];
    if (!Number.isFinite(v) || v === p.default) continue;
    const span = Number.isFinite(p.max - p.min) && p.max > p.min ? p.max - p.min : Math.max(1, Math.abs(p.default));
    return Math.max(-1, Math.min(1, (v - p.default) / span)) || Math.sign(v - p.default) * 1e-3;
  }
  return 0;
}

/**
 * The look of a method (a run's method, a form's, or a run holding one as `method`):
 * `{colour, dash, marker, hollow}`; `dash` is null for a solid line. The catalog's place of
 * the method fixes its colour and marker; an id not in the catalog gets one from its name.
 */
export function methodStyle(catalog, method) {
  const m = method?.method ?? method ?? {};
  const methods = catalog?.methods ?? [];
  const index = methods.findIndex((x) => x.id === m.id);
  const slot = index >= 0 ? index : methods.length + (hash(m.id ?? '') % COLOURS.length);
  let colour = methods[index]?.instrument ? INSTRUMENT : COLOURS[slot % COLOURS.length];
  // Past the tenth method the colours come round again, each with the next marker, so no
  // two of the first hundred share both.
  const marker = MARKERS[(slot + Math.floor(slot / COLOURS.length)) % MARKERS.length];
  const t = offset(methods[index], paramsOf(m));
  // At least a third of the way to black or white, so a nearby parameter still reads apart.
  if (t !== 0) colour = shade(colour, Math.sign(t) * Math.min(0.65, 0.32 + 0.6 * Math.abs(t)));
  let dash = null;
  if (m.composition) {
    const c = (catalog?.compositions ?? []).findIndex((x) => x.id === m.composition);
    dash = DASHES[(c >= 0 ? c : hash(m.composition)) % DASHES.length];
  }
  return { colour, dash, marker, hollow: t !== 0 };
}

// Marker outlines around (x, y) with radius r, drawn with moveTo/lineTo/arc/closePath on a
// Path2D or an SvgContext; `open` shapes are strokes only.
const POLY = {
  square: [[-0.8, -0.8], [0.8, -0.8], [0.8, 0.8], [-0.8, 0.8]],
  triangle: [[0, -1.1], [0.95, 0.65], [-0.95, 0.65]],
  'triangle-down': [[0, 1.1], [0.95, -0.65], [-0.95, -0.65]],
  diamond: [[0, -1.15], [0.9, 0], [0, 1.15], [-0.9, 0]],
  star: Array.from({ length: 10 }, (_, k) => {
    const r = k % 2 ? 0.5 : 1.15;
    const a = -Math.PI / 2 + (k * Math.PI) / 5;
    return [r * Math.cos(a), r * Math.sin(a)];
  }),
  pentagon: Array.from({ length: 5 }, (_, k) => [Math.cos(-Math.PI / 2 + (2 * k * Math.PI) / 5), Math.sin(-Math.PI / 2 + (2 * k * Math.PI) / 5)]),
  hexagon: Array.from({ length: 6 }, (_, k) => [Math.cos((k * Math.PI) / 3), Math.sin((k * Math.PI) / 3)]),
};
const OPEN = {
  cross: [[[-0.8, -0.8], [0.8, 0.8]], [[-0.8, 0.8], [0.8, -0.8]]],
  plus: [[[0, -1.05], [0, 1.05]], [[-1.05, 0], [1.05, 0]]],
};

/** Whether a marker shape is drawn as strokes only (it has no inside to fill). */
export const isOpen = (marker) => marker in OPEN;

/** The fill of a method's marker drawn in `colour`: none for an open shape, white for a
 *  hollow one (parameters off their defaults), else the colour. */
export function markerFill(style, colour = style.colour) {
  if (isOpen(style.marker)) return 'none';
  return style.hollow ? '#fff' : colour;
}

/** Adds a marker at (x, y) of radius r to `pen` (a Path2D, a canvas context or an SvgContext). */
export function addMarker(pen, marker, x, y, r) {
  if (OPEN[marker]) {
    for (const [[ax, ay], [bx, by]] of OPEN[marker]) {
      pen.moveTo(x + ax * r, y + ay * r);
      pen.lineTo(x + bx * r, y + by * r);
    }
  } else if (POLY[marker]) {
    POLY[marker].forEach(([px, py], k) => (k ? pen.lineTo(x + px * r, y + py * r) : pen.moveTo(x + px * r, y + py * r)));
    pen.closePath();
  } else {
    pen.moveTo(x + r, y);
    pen.arc(x, y, r, 0, 2 * Math.PI);
    pen.closePath();
  }
}

