// The Map view's settings, pure: its axes (a path into the scene and its values, written as
// a list or spaced linearly or logarithmically), the method, integral and colouring it shows;
// the body of `POST /sweep` for the Explore form's state and these settings; their URL form
// beside the form's own (`?view=map&<form state>&map.axis=params.epsilon:linspace:0,0.5,11`);
// where a cell sits on the grid (the last axis varies fastest and runs along x); the paths an
// axis may take for a scene; and the presets (presets.json) the catalog can resolve.

import { applicable, findMethod, findPreset, findSystem } from '../data/catalog.js';
import { coordinateNames, isCustom } from '../data/custom.js';
import { defaultState, encodeState, parseList, requestBody } from '../data/state.js';

/** How an axis gives its values, in the order the kind select lists them. */
export const KINDS = ['linspace', 'logspace', 'values'];

/** The view shows one or two axes (the API takes up to three). */
export const MAX_AXES = 2;

/** Colourings: the verdict of each cell, or log₁₀ of its largest error. */
export const COLORS = ['verdict', 'log'];

/** The settings of a map no link or preset has set. */
export function defaultSettings() {
  return {
    axes: [{ path: 'step', kind: 'logspace', numbers: [0.01, 1, 9] }],
    method: 0,
    integral: '',
    color: 'verdict',
    run: false,
  };
}

/** An axis as the API takes it: `{path, linspace | logspace | values: numbers}`. */
export function axisRequest(axis) {
  return { path: axis.path.trim(), [axis.kind]: [...axis.numbers] };
}

/** The body of `POST /sweep`: the form's scene and methods (as `requestBody` writes them with
 *  the `catalog`) with the axes. */
export function sweepBody(state, settings, catalog) {
  return { ...requestBody(state, catalog), axes: settings.axes.map(axisRequest) };
}

/**
 * The values an axis stands for, as the server expands them (n values from start to stop,
 * both included; logspace evenly in the logarithm); null while the axis cannot be expanded.
 */
export function expandAxis(axis) {
  const xs = axis.numbers;
  if (!xs.length || xs.some((x) => !Number.isFinite(x))) return null;
  if (axis.kind === 'values') return [...xs];
  if (xs.length !== 3) return null;
  const [start, stop, n] = xs;
  if (!Number.isInteger(n) || n < 1) return null;
  if (axis.kind === 'logspace' && !(start > 0 && stop > 0)) return null;
  if (n === 1) return [start];
  return Array.from({ length: n }, (_, k) => {
    if (k === n - 1) return stop;
    const f = k / (n - 1);
    return axis.kind === 'logspace' ? start * (stop / start) ** f : start + (stop - start) * f;
  });
}

/**
 * What is wrong with an axis before it is sent, as `{path, message}` in the API's paths
 * (`axes[0].path`, `axes[0].linspace`), so a mistake is marked where the server would mark it.
 */
export function checkAxis(axis, i) {
  const out = [];
  const at = (field, message) => out.push({ path: `axes[${i}].${field}`, message });
  if (axis.path.trim() === '') at('path', 'name what the axis sets, e.g. step or params.<name>');
  const xs = axis.numbers;
  if (xs.some((x) => !Number.isFinite(x))) at(axis.kind, 'comma-separated numbers, please');
  else if (axis.kind === 'values' && xs.length === 0) at(axis.kind, 'give at least one value');
  else if (axis.kind !== 'values' && xs.length !== 3) at(axis.kind, 'three numbers: start, stop, count');
  else if (axis.kind !== 'values' && !(Number.isInteger(xs[2]) && xs[2] >= 1)) at(axis.kind, 'the count is a whole number ≥ 1');
  else if (axis.kind === 'logspace' && !(xs[0] > 0 && xs[1] > 0)) at(axis.kind, 'logspace takes start and stop > 0 (values, not exponents)');
  return out;
}

/** The number of cells of the axes' product (null while an axis cannot be expanded). */
export function cellCount(axes) {
  let n = 1;
  for (const a of axes) {
    const values = expandAxis(a);
    if (!values) return null;
    n *= values.length;
  }
  return n;
}

/** A cell's index on each axis: cell = (i0·n1 + i1)·n2 + i2, the last axis fastest. */
export function gridPosition(cell, counts) {
  const out = new Array(counts.length);
  let rest = cell;
  for (let a = counts.length - 1; a >= 0; a--) {
    out[a] = rest % counts[a];
    rest = Math.floor(rest / counts[a]);
  }
  return out;
}

/** The grid of a map: x along the last axis, y along the first (one row for a single axis). */
export function gridShape(counts) {
  return { nx: counts[counts.length - 1] ?? 0, ny: counts.length > 1 ? counts[0] : 1 };
}

/** Where a cell is drawn: column x (last axis) and row y (first axis; 0 for one axis). */
export function cellXY(cell, counts) {
  const idx = gridPosition(cell, counts);
  return { x: idx[idx.length - 1], y: idx.length > 1 ? idx[0] : 0 };
}

/** The cell drawn at column x, row y (the inverse of cellXY for one or two axes). */
export function cellAtXY(x, y, counts) {
  return counts.length > 1 ? y * counts[counts.length - 1] + x : x;
}

/** The settings' query pairs, only where they differ from the defaults. */
export function encodeSettings(settings) {
  const d = defaultSettings();
  const out = [];
  const axes = settings.axes.map((a) => `${a.path.trim()}:${a.kind}:${a.numbers.map(String).join(',')}`);
  const same = axes.join('|') === d.axes.map((a) => `${a.path}:${a.kind}:${a.numbers.join(',')}`).join('|');
  if (!same) for (const a of axes) out.push(['map.axis', a]);
  if (settings.method !== d.method) out.push(['map.method', String(settings.method)]);
  // The energy is the integral shown when the link names none (controls.js).
  if (settings.integral && settings.integral !== 'energy') out.push(['map.integral', settings.integral]);
  if (settings.color !== d.color) out.push(['map.color', settings.color]);
  return out;
}

/** The view's query string (without `?`): the form's state, then the map's settings. */
export function mapQuery(state, catalog, settings, run = false) {
  const parts = ['view=map', encodeState({ ...state, run: false }, catalog)];
  for (const [k, v] of encodeSettings(settings)) parts.push(`${k}=${esc(v)}`);
  if (run) parts.push('run=1');
  return parts.filter(Boolean).join('&');
}

/** The settings a query string describes, with `warnings` for what it could not use. */
export function decodeSettings(query) {
  const p = new URLSearchParams(query);
  const settings = defaultSettings();
  const warnings = [];
  const axes = [];
  for (const text of p.getAll('map.axis')) {
    const parts = text.split(':');
    const kind = parts.length >= 3 ? parts[parts.length - 2] : '';
    if (!KINDS.includes(kind)) {
      warnings.push(`map axis "${text}" is not path:kind:numbers (kind ${KINDS.join(', ')}); left out`);
      continue;
    }
    axes.push({ path: parts.slice(0, -2).join(':'), kind, numbers: parseList(parts[parts.length - 1]) });
  }
  if (axes.length > MAX_AXES) warnings.push(`the map shows at most ${MAX_AXES} axes; the others were left out`);
  if (axes.length) settings.axes = axes.slice(0, MAX_AXES);
  const method = Number(p.get('map.method'));
  if (p.has('map.method') && Number.isInteger(method) && method >= 0) settings.method = method;
  if (p.has('map.integral')) settings.integral = p.get('map.integral');
  if (COLORS.includes(p.get('map.color'))) settings.color = p.get('map.color');
  settings.run = p.get('run') === '1';
  return { settings, warnings };
}

/**
 * The paths an axis may take for a state: its system's parameters, step and t_end, each
 * coordinate of q and q̇ (as many as the state's q has), and the parameters of its methods
 * (all of them, or one).
 */
export function axisPaths(state, catalog) {
  const custom = isCustom(state.system);
  const system = custom ? null : findSystem(catalog, state.system);
  const params = custom ? Object.keys(state.system.parameters ?? {}) : (system?.params ?? []).map((p) => p.name);
  // q's size: the form's (a preset may change it), else the system's.
  const dof = state.q?.length || (custom ? coordinateNames(state.system).length : system?.dof ?? 0);
  const out = [...params.map((n) => `params.${n}`), 'step', 't_end'];
  const methodParams = state.methods.map((m) => (findMethod(catalog, m.id)?.params ?? []).map((p) => p.name));
  for (const name of new Set(methodParams.flat())) out.push(`methods.${name}`);
  methodParams.forEach((names, i) => names.forEach((n) => out.push(`methods[${i}].${n}`)));
  for (const key of ['q', 'v']) for (let i = 0; i < dof; i++) out.push(`${key}[${i}]`);
  return out;
}

/**
 * The presets (presets.json) whose system, preset, methods and parameters the catalog
 * has, their methods applying to their system; a preset without `methods` takes the
 * catalog's default methods.
 */
export function mapPresets(presets, catalog) {
  return presets.filter((x) => {
    const system = findSystem(catalog, x.scene?.system);
    if (!system || (x.scene.preset && !findPreset(system, x.scene.preset))) return false;
    const methods = x.scene.methods ?? [];
    const methodsKnown = applicable(catalog, system.id, methods).length === methods.length && methods.every((m) => {
      const info = findMethod(catalog, m.id);
      return info && Object.keys(m).every((k) => k === 'id' || (info.params ?? []).some((p) => p.name === k));
    });
    const paramsKnown = Object.keys(x.scene.params ?? {}).every((k) => system.params.some((p) => p.name === k));
    return methodsKnown && paramsKnown && (x.scene.integrals ?? []).every((i) => system.integrals.includes(i));
  });
}

/** The form state and map settings a preset stands for (it runs: `run` is set). */
export function presetSetup(preset, catalog) {
  const s = preset.scene;
  const state = defaultState(catalog, s.system, s.preset);
  Object.assign(state.params, s.params ?? {});
  for (const key of ['step', 't_end', 'points']) if (s[key] !== undefined) state[key] = s[key];
  if (s.methods) {
    state.methods = s.methods.map(({ id, ...params }) => ({ id, params: { ...defaultParams(catalog, id), ...params } }));
  }
  if (s.integrals) state.integrals = [...s.integrals];
  const axes = preset.axes.map((a) => {
    const kind = KINDS.find((k) => Array.isArray(a[k]));
    return { path: a.path, kind, numbers: [...a[kind]] };
  });
  const settings = { axes, method: preset.method ?? 0, integral: preset.integral ?? '', color: preset.color ?? 'verdict', run: true };
  return { state, settings };
}

function defaultParams(catalog, id) {
  return Object.fromEntries((findMethod(catalog, id)?.params ?? []).map((p) => [p.name, p.default]));
}

// As state.js writes its values: commas, colons, brackets and slashes plainly, for readable links.
function esc(s) {
  return encodeURIComponent(s).replace(/%2C/g, ',').replace(/%3A/g, ':').replace(/%5B/g, '[').replace(/%5D/g, ']').replace(/%2F/g, '/');
}
