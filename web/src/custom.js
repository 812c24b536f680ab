// A system of the user's own, given as formulas: the object `"system"` takes in a request
// (name, passenger and driver names, parameters with their values, the potentials U and V_d,
// the passenger columns of the constraint matrix A(ζ)). Pure functions over that object: a
// copy of a built-in's `formulas` from the catalog, the integrals the server may offer, its
// URL form, and the labels that name a scene's system, built-in or not (in words and as a
// file-name stem).

import { findPreset, findSystem, presetLabel } from './catalog.js';

/** The system select's value for "Custom system" (no built-in id looks like it). */
export const CUSTOM = '(custom)';

/** Sizes the API takes: passengers, and constraint rows from 1 to passengers − 1. */
export const MIN_PASSENGERS = 2;
export const MAX_PASSENGERS = 6;

/** Integrals every custom system has, in the order the server lists them. */
const ALWAYS = ['energy', 'passenger_energy', 'driver_energy', 'constraint'];

/** What the editor shows for a built-in the catalog gives no formulas for. */
const BLANK = {
  name: 'My system',
  passenger: ['x1', 'x2'],
  driver: 'zeta',
  parameters: {},
  passenger_potential: '(x1^2 + x2^2)/2',
  driver_potential: 'zeta^2/2',
  constraints: [['1', 'zeta']],
};

export function isCustom(system) {
  return system !== null && typeof system === 'object';
}

/** A deep copy of a custom system, with its fields in the API's order. */
export function copyCustom(sys) {
  return {
    name: sys.name ?? '',
    passenger: [...(sys.passenger ?? [])],
    driver: sys.driver ?? '',
    parameters: { ...(sys.parameters ?? {}) },
    passenger_potential: sys.passenger_potential ?? '',
    driver_potential: sys.driver_potential ?? '',
    constraints: (sys.constraints ?? []).map((row) => [...row]),
  };
}

/**
 * A built-in system's formula form (its catalog `formulas`), with parameters at `params`
 * where given; a small template when the catalog has no formulas for it.
 */
export function customFrom(catalog, systemId, params = {}) {
  const formulas = findSystem(catalog, systemId)?.formulas;
  const sys = copyCustom(formulas ?? BLANK);
  for (const name of Object.keys(sys.parameters)) {
    if (typeof params[name] === 'number') sys.parameters[name] = params[name];
  }
  return sys;
}

/** The built-ins the editor can start from: those with a formula form. */
export function startingPoints(catalog) {
  return catalog.systems.filter((s) => s.formulas);
}

/** The integrals the server may offer: the latitude only for two passengers and one
 *  constraint (it also needs a quadratic U, which the server checks). */
export function customIntegrals(sys) {
  const latitude = sys.passenger.length === 2 && sys.constraints.length === 1;
  return latitude ? [...ALWAYS.slice(0, 3), 'latitude', 'constraint'] : [...ALWAYS];
}

/** The integrals a custom state starts with: those every custom system has. */
export function defaultCustomIntegrals() {
  return [...ALWAYS];
}

/** A scene's system as a label names it: a built-in's name, or the custom system's. */
export function systemName(system, catalog) {
  if (isCustom(system)) return system.name?.trim() || 'Custom system';
  return findSystem(catalog, system)?.name ?? String(system ?? '');
}

/** A one-line description of a resolved scene: system, preset, the parameters (those the
 *  preset does not set already), h and t_end. */
export function sceneCaption(scene, catalog) {
  const custom = isCustom(scene.system);
  const preset = custom ? null : findPreset(findSystem(catalog, scene.system), scene.preset);
  const params = custom ? scene.system.parameters ?? {} : scene.params ?? {};
  const shown = Object.entries(params).filter(([k, v]) => preset?.params?.[k] !== v);
  return [
    custom ? `${systemName(scene.system, catalog)} (custom)` : systemName(scene.system, catalog),
    preset ? presetLabel(preset) : '',
    ...shown.map(([k, v]) => `${k} = ${v}`),
    // π/10 reads 0.314159, not 0.3141592653589793.
    Number.isFinite(scene.step) ? `h = ${Number(scene.step.toPrecision(6))}` : '',
    Number.isFinite(scene.t_end) ? `t_end = ${scene.t_end}` : '',
  ]
    .filter(Boolean)
    .join(' · ');
}

/**
 * The query pairs of a custom system: `custom=<name>`, `passenger=x1,x2`, `driver=zeta`,
 * `param.<name>=<value>` in order, `U=…`, `Vd=…` and one `A=…` per constraint row (entries
 * comma-separated). Commas and `%` inside an item are written %2C and %25.
 */
export function encodeCustom(sys) {
  const out = [
    ['custom', sys.name],
    ['passenger', joinItems(sys.passenger)],
    ['driver', sys.driver],
  ];
  for (const [name, value] of Object.entries(sys.parameters)) out.push([`param.${name}`, String(value)]);
  out.push(['U', sys.passenger_potential], ['Vd', sys.driver_potential]);
  for (const row of sys.constraints) out.push(['A', joinItems(row)]);
  return out;
}

/** The custom system of a query (URLSearchParams), or null when it names none. Parameter
 *  values that do not parse are kept as NaN for the form to mark. */
export function decodeCustom(p) {
  if (!p.has('custom')) return null;
  const parameters = {};
  for (const [key, value] of p) {
    if (key.startsWith('param.')) parameters[key.slice(6)] = Number(value);
  }
  return {
    name: p.get('custom'),
    passenger: splitItems(p.get('passenger') ?? ''),
    driver: p.get('driver') ?? '',
    parameters,
    passenger_potential: p.get('U') ?? '',
    driver_potential: p.get('Vd') ?? '',
    constraints: p.getAll('A').map(splitItems),
  };
}

/**
 * The custom system the editor's inputs describe (`fields`: the texts of its inputs, the
 * parameters as [name, value] pairs, the constraints as rows of entries) and the inputs that
 * cannot be sent as `invalid` ({path, message}): a parameter without a name, given twice or
 * whose value is not a number. Formulas go as typed: the server checks them and says where.
 */
export function customFromFields(fields) {
  const invalid = [];
  const parameters = {};
  for (const [rawName, text] of fields.parameters) {
    const name = rawName.trim();
    if (!name) {
      invalid.push({ path: 'system.parameters', message: 'a parameter needs a name' });
      continue;
    }
    const path = `system.parameters.${name}`;
    const value = String(text).trim() === '' ? NaN : Number(text);
    if (Object.hasOwn(parameters, name)) invalid.push({ path, message: `parameter '${name}' is given twice` });
    else if (!Number.isFinite(value)) invalid.push({ path, message: `parameter '${name}' needs a number` });
    parameters[name] = value;
  }
  const system = {
    name: fields.name,
    passenger: parseNames(fields.passenger),
    driver: fields.driver.trim(),
    parameters,
    passenger_potential: fields.passenger_potential,
    driver_potential: fields.driver_potential,
    constraints: fields.constraints.map((row) => [...row]),
  };
  return { system, invalid };
}

/** Comma-separated names as a list (blank items kept, for the server to name). */
export function parseNames(text) {
  const t = String(text).trim();
  return t === '' ? [] : t.split(',').map((s) => s.trim());
}

function joinItems(items) {
  return items.map((s) => String(s).replace(/[%,]/g, (c) => (c === '%' ? '%25' : '%2C'))).join(',');
}

function splitItems(text) {
  if (text === '') return [];
  return text.split(',').map((s) => s.replace(/%(25|2C)/gi, (m) => (m === '%25' ? '%' : ',')));
}

/** `s` as a part of a file name: lower case, runs of other characters as one `-`. */
export const slug = (s) => String(s).toLowerCase().replace(/[^a-z0-9_]+/g, '-').replace(/^-|-$/g, '');

/** A system for a file name: a built-in's id, a custom system's name in lower case and
 *  dashes (`custom` when it has none). */
export function systemSlug(system, catalog) {
  return isCustom(system) ? slug(systemName(system, catalog)) || 'custom' : slug(system ?? 'scene');
}

/** A scene as a file-name stem: `nhlab-<system>-<preset>`. */
export function sceneStem(scene, catalog) {
  return ['nhlab', systemSlug(scene?.system, catalog), scene?.preset ? slug(scene.preset) : ''].filter(Boolean).join('-');
}
