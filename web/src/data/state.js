// The page state and its URL form, so a link reproduces a plot. The query string holds the
// system and preset always, and every other field only where it differs from what the preset
// (or the page) would choose, which keeps the paper's links short:
//   ?system=<system id>&preset=<preset id>&smooth=1&run=1
// Methods are written `id` or `id:p1:p2` (parameters in the order /systems lists them), e.g.
// `methods=<id>:0.5,<id>:0.4,<id>`, and a composition after `@`
// (`<id>@<composition>`); the method given as a tableau (PRK) adds its stored tableau and,
// where it is not `stage`, its constraint (`<id>:gauss3`, `<id>:gauss2:midpoint@p4s3`). The
// defaults (methods, window) come from the catalog by the rules of catalog.js. A custom
// system (custom.js) is written field by field instead of `system` and `preset`
// (customurl.js); it has no preset, so its initial state and times are written too:
//   ?custom=<name>&passenger=x1,x2&driver=zeta&param.k=1&U=…&Vd=…&A=…&q=…&v=…&step=…&t_end=…
// A link's methods that do not apply to its system (one made for the paper's class alone, on
// a system outside it) are left out with a warning; an unknown tableau falls back to the
// default one, with a warning too. Pure functions over the /systems catalog.

import { DEFAULT_CONSTRAINT, applicable, composableAt, defaultMethods, defaultWindow, findMethod, findPreset, findSystem, tableauChoice, takesTableau } from './catalog.js';
import { copyCustom, defaultCustomIntegrals, isCustom } from './custom.js';
import { decodeCustom, encodeCustom } from './customurl.js';

export { defaultWindow, findPreset, findSystem };

/** The state the page starts from for a system and preset (the preset's values, the catalog's
 *  default methods, the preset's default window). */
export function defaultState(catalog, systemId, presetId) {
  const system = findSystem(catalog, systemId) ?? catalog.systems[0];
  const preset = findPreset(system, presetId) ?? system.presets?.[0];
  const params = Object.fromEntries(system.params.map((p) => [p.name, p.default]));
  Object.assign(params, preset?.params ?? {});
  return {
    system: system.id,
    preset: preset?.id ?? '',
    params,
    q: preset?.q ? [...preset.q] : [],
    v: preset?.v ? [...preset.v] : [],
    step: preset?.step ?? null,
    t_end: preset?.t_end ?? null,
    points: 1000,
    methods: applicable(catalog, system.id, defaultMethods(catalog)),
    integrals: [...system.integrals],
    stat: 'mean',
    smooth: false,
    window: defaultWindow(preset?.t_end),
    run: false,
  };
}

/** The state of a custom system `sys` (its parameters carry their values): no preset, an
 *  initial state and times to fill, the integrals every custom system has. */
export function defaultCustomState(catalog, sys) {
  return {
    system: copyCustom(sys),
    preset: '',
    params: {},
    q: [],
    v: [],
    step: null,
    t_end: null,
    points: 1000,
    methods: defaultMethods(catalog),
    integrals: defaultCustomIntegrals(sys),
    stat: 'mean',
    smooth: false,
    window: defaultWindow(undefined),
    run: false,
  };
}

/** The query string for a state (without `?`). */
export function encodeState(state, catalog) {
  const custom = isCustom(state.system);
  const d = custom ? defaultCustomState(catalog, state.system) : defaultState(catalog, state.system, state.preset);
  const out = custom ? encodeCustom(state.system) : [['system', state.system], ['preset', state.preset]];
  if (custom) d.window = defaultWindow(state.t_end);
  for (const [name, value] of Object.entries(custom ? {} : state.params)) {
    if (!sameNumber(value, d.params[name])) out.push([`param.${name}`, num(value)]);
  }
  for (const key of ['q', 'v']) {
    if (list(state[key]) !== list(d[key])) out.push([key, list(state[key])]);
  }
  for (const key of ['step', 't_end', 'points']) {
    if (!sameNumber(state[key], d[key])) out.push([key, num(state[key])]);
  }
  const methods = encodeMethods(state.methods, catalog);
  if (methods !== encodeMethods(d.methods, catalog)) out.push(['methods', methods]);
  if (state.integrals.join(',') !== d.integrals.join(',')) out.push(['integrals', state.integrals.join(',')]);
  if (state.stat !== d.stat) out.push(['stat', state.stat]);
  if (state.smooth) out.push(['smooth', '1']);
  if (!sameNumber(state.window, d.window)) out.push(['window', num(state.window)]);
  if (state.run) out.push(['run', '1']);
  // Commas and colons are legal in a query; leaving them unescaped keeps links readable.
  return out
    .map(([k, v]) => `${esc(k)}=${esc(v)}`)
    .join('&');
}

/**
 * The state a query string describes, with `warnings` for what it could not use (an unknown
 * system or method). Numbers that do not parse are kept as NaN for the server to reject.
 */
export function decodeState(query, catalog) {
  const p = new URLSearchParams(query);
  const warnings = [];
  const custom = decodeCustom(p);
  if (custom) {
    const state = defaultCustomState(catalog, custom);
    readFields(p, state, catalog, warnings);
    if (!p.has('window')) state.window = defaultWindow(state.t_end);
    return { state, warnings };
  }
  let systemId = p.get('system');
  if (systemId !== null && !findSystem(catalog, systemId)) {
    warnings.push(`unknown system "${systemId}" in the link; showing ${catalog.systems[0].id}`);
    systemId = null;
  }
  const system = findSystem(catalog, systemId) ?? catalog.systems[0];
  let presetId = p.get('preset');
  if (presetId !== null && presetId !== '' && !findPreset(system, presetId)) {
    warnings.push(`unknown preset "${presetId}" for ${system.id} in the link; showing the first preset`);
    presetId = null;
  }
  const state = defaultState(catalog, system.id, presetId);
  if (presetId === '') state.preset = '';
  for (const [key, value] of p) {
    if (key.startsWith('param.')) state.params[key.slice(6)] = Number(value);
  }
  readFields(p, state, catalog, warnings);
  return { state, warnings };
}

// The fields a built-in's and a custom system's links share, over `state`'s defaults.
function readFields(p, state, catalog, warnings) {
  for (const key of ['q', 'v']) if (p.has(key)) state[key] = parseList(p.get(key));
  // An empty value (`step=`) is an empty field, the preset's value: not 0.
  for (const key of ['step', 't_end', 'points']) if (p.has(key)) state[key] = p.get(key).trim() === '' ? null : Number(p.get(key));
  if (p.has('methods')) {
    const methods = decodeMethods(p.get('methods'), catalog, warnings);
    state.methods = applicable(catalog, state.system, methods);
    for (const m of methods.filter((x) => !state.methods.includes(x))) {
      warnings.push(`${findMethod(catalog, m.id)?.name ?? m.id} does not apply to ${findSystem(catalog, state.system)?.name ?? 'this system'}; left out`);
    }
  }
  if (p.has('integrals')) state.integrals = p.get('integrals').split(',').filter(Boolean);
  if (p.get('stat') === 'max') state.stat = 'max';
  state.smooth = p.get('smooth') === '1';
  if (p.has('window')) state.window = Number(p.get('window'));
  state.run = p.get('run') === '1';
}

/** The body of `POST /simulate` for a state: a custom system goes as its object, without
 *  preset and params (its parameters carry their values). With the `catalog`, a built-in's
 *  integrals are left out while they are all it lists: the server then measures what the
 *  scene has (a preset or a parameter may take the system out of the paper's class, and the
 *  passenger and driver energies with it). */
export function requestBody(state, catalog) {
  const custom = isCustom(state.system);
  const body = { system: custom ? copyCustom(state.system) : state.system };
  if (state.preset && !custom) body.preset = state.preset;
  if (!custom) body.params = { ...state.params };
  // Unset fields (empty inputs) are left to the preset.
  for (const key of ['q', 'v']) if (state[key]?.length) body[key] = state[key];
  for (const key of ['step', 't_end']) if (state[key] !== null && state[key] !== undefined) body[key] = state[key];
  body.methods = state.methods.map((m) => ({
    id: m.id,
    ...m.params,
    // A PRK method's tableau and constraint, as the request takes them beside its id.
    ...(m.tableau ? { tableau: m.tableau } : {}),
    ...(m.constraint ? { constraint: m.constraint } : {}),
    ...(m.composition ? { composition: m.composition } : {}),
  }));
  const listed = !custom && catalog ? findSystem(catalog, state.system)?.integrals : null;
  if (listed?.join(',') !== state.integrals.join(',')) body.integrals = state.integrals;
  body.points = state.points;
  return body;
}

export function parseList(text) {
  const t = String(text).trim();
  if (t === '') return [];
  return t.split(/[\s,;]+/).filter(Boolean).map(Number);
}

function encodeMethods(methods, catalog) {
  return methods
    .map((m) => {
      const info = findMethod(catalog, m.id);
      const values = (info?.params ?? []).map((p) => num(m.params[p.name] ?? p.default));
      // After the parameters, a PRK method's tableau and its constraint where not `stage`.
      if (takesTableau(catalog, m.id)) {
        const choice = tableauChoice(catalog, m.tableau, m.constraint);
        values.push(choice.tableau, ...(choice.constraint === DEFAULT_CONSTRAINT ? [] : [choice.constraint]));
      }
      const item = [m.id, ...values].join(':');
      return m.composition ? `${item}@${m.composition}` : item;
    })
    .join(',');
}

function decodeMethods(text, catalog, warnings) {
  const out = [];
  for (const item of text.split(',').filter(Boolean)) {
    const [name, composition] = item.split('@');
    const [id, ...values] = name.split(':');
    const info = findMethod(catalog, id);
    if (!info) {
      warnings.push(`unknown method "${id}" in the link; left out`);
      continue;
    }
    const params = {};
    info.params.forEach((p, i) => {
      params[p.name] = i < values.length ? Number(values[i]) : p.default;
    });
    const method = { id, params };
    // A PRK method: its tableau and constraint follow the parameters (it has none).
    const tableau = takesTableau(catalog, id) ? readTableau(values.slice(info.params.length), catalog, warnings) : null;
    if (tableau) Object.assign(method, { tableau: tableau.tableau, constraint: tableau.constraint });
    const composable = tableau ? composableAt(info, params, tableau.entry).composable : info.composable;
    const known = (catalog.compositions ?? []).some((c) => c.id === composition);
    if (composition && !known) warnings.push(`unknown composition "${composition}" in the link; left out`);
    if (known && !composable) {
      const what = tableau?.entry ? `${tableau.entry.label} is not symmetric, so it` : id;
      warnings.push(`${what} takes no composition; "${composition}" left out`);
    }
    out.push(known && composable ? { ...method, composition } : method);
  }
  return out;
}

// A PRK method's `tableau:constraint` from a link, as the catalog can run it: an unknown
// tableau or a constraint it does not take falls back (tableauChoice), with a warning.
function readTableau([tableau, constraint], catalog, warnings) {
  const choice = tableauChoice(catalog, tableau || undefined, constraint || undefined);
  if (tableau && tableau !== choice.tableau) warnings.push(`unknown tableau "${tableau}" in the link; ${choice.tableau} instead`);
  if (constraint && constraint !== choice.constraint) warnings.push(`${choice.tableau} takes no constraint "${constraint}"; ${choice.constraint} instead`);
  return choice;
}

function num(v) {
  return v === null || v === undefined ? '' : String(v);
}

function list(a) {
  return (a ?? []).map(num).join(',');
}

function sameNumber(a, b) {
  return num(a) === num(b);
}

/** A value for the URL's query, encoded but for what keeps it readable: commas, colons,
 *  slashes and spaces (as +) for formulas and lists, `@` for compositions. */
export function esc(s) {
  return encodeURIComponent(s).replace(/%2C/g, ',').replace(/%3A/g, ':').replace(/%40/g, '@').replace(/%2F/g, '/').replace(/%20/g, '+');
}
