// A system of the user's own, given as formulas: the object `"system"` takes in a request,
// in the paper's form (name, passenger and driver names, parameters with their values, the
// potentials U and V_d, the passenger columns of the constraint matrix A(ζ)) or the general
// one (coordinates, a constant mass matrix M, a potential V(q), the rows of A(q), named
// invariants, whether to look for the paper's class in it). Pure functions over that object:
// a copy of a built-in's `formulas` or `general` form from the catalog, one form written in
// the other, the integrals the server may offer, and the labels that name a scene's system,
// built-in or not (in words and as a file-name stem). The editor's inputs are read into it
// by customfields.js, its URL form is in customurl.js.

import { findPreset, findSystem, presetLabel } from './catalog.js';

/** The system select's value for "Custom system" (no built-in id looks like it). */
export const CUSTOM = '(custom)';

/** Integrals every custom system in the paper's form has, in the order the server lists them. */
const ALWAYS = ['energy', 'passenger_energy', 'driver_energy', 'constraint'];

/** Integrals a system in the general form has only where nhlab finds the paper's class in it. */
export const CLASS_ONLY = ['passenger_energy', 'driver_energy', 'latitude'];

/** What the editor shows for a system the catalog gives no formulas for. */
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

/** Whether a custom system is in the general form (it names its `coordinates`). */
export function isGeneral(sys) {
  return isCustom(sys) && Array.isArray(sys.coordinates);
}

/** A custom system's form: `general` or `paper`. */
export function formOf(sys) {
  return isGeneral(sys) ? 'general' : 'paper';
}

/** A deep copy of a custom system, with its fields in the API's order (as the server writes
 *  them back: no `mass` for the identity, no `invariants` when there are none). */
export function copyCustom(sys) {
  if (isGeneral(sys)) {
    const invariants = { ...(sys.invariants ?? {}) };
    return {
      name: sys.name ?? '',
      coordinates: [...sys.coordinates],
      parameters: { ...(sys.parameters ?? {}) },
      ...(Array.isArray(sys.mass) ? { mass: sys.mass.map((m) => (Array.isArray(m) ? [...m] : m)) } : {}),
      potential: sys.potential ?? '',
      constraints: (sys.constraints ?? []).map((row) => [...row]),
      ...(Object.keys(invariants).length ? { invariants } : {}),
      detect_class: sys.detect_class !== false,
    };
  }
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

/** How a mass is given: `identity` (none), `diagonal` (a list) or `full` (rows). */
export function massMode(mass) {
  if (!Array.isArray(mass)) return 'identity';
  return mass.length > 0 && mass.every(Array.isArray) ? 'full' : 'diagonal';
}

/** The names of a custom system's coordinates, in the order q and q̇ list them (the paper's
 *  form: the passengers, then the driver). */
export function coordinateNames(sys) {
  return isGeneral(sys) ? [...sys.coordinates] : [...sys.passenger, sys.driver];
}

/**
 * A built-in system written as formulas, with parameters at `params` where given: in `form`
 * (`paper`: its catalog `formulas`; `general`: its `general`), or without `form` in the
 * paper's where it has one, else the general one; a small template when the catalog has
 * neither.
 */
export function customFrom(catalog, systemId, params = {}, form) {
  const system = findSystem(catalog, systemId);
  const general = form === 'general' || (form !== 'paper' && !system?.formulas && system?.general);
  const source = general ? system?.general ?? toGeneral(BLANK) : system?.formulas ?? BLANK;
  const sys = copyCustom(source);
  for (const name of Object.keys(sys.parameters)) {
    if (typeof params[name] === 'number') sys.parameters[name] = params[name];
  }
  return sys;
}

/** The built-ins the editor can start from, per form: those with a paper's form, and every
 *  one in the general form. */
export function startingPoints(catalog) {
  return {
    paper: catalog.systems.filter((s) => s.formulas),
    general: catalog.systems.filter((s) => s.general),
  };
}

/** A paper's-form system in the general form: the driver last, V = U + V_d, unit masses, A's
 *  driver column zero. The same system: nhlab finds the paper's class in it. */
export function toGeneral(sys) {
  return {
    name: sys.name,
    coordinates: [...sys.passenger, sys.driver],
    parameters: { ...sys.parameters },
    potential: `(${sys.passenger_potential || '0'}) + (${sys.driver_potential || '0'})`,
    constraints: sys.constraints.map((row) => [...row, '0']),
    detect_class: true,
  };
}

/** A general-form system in the paper's form, as far as it goes: the last coordinate as the
 *  driver, V as U (V_d zero), A without its last column; M and the invariants are left out
 *  (the server says what does not fit the paper's form). */
export function toPaper(sys) {
  const names = sys.coordinates;
  return {
    name: sys.name,
    passenger: names.slice(0, -1),
    driver: names[names.length - 1] ?? '',
    parameters: { ...sys.parameters },
    passenger_potential: sys.potential,
    driver_potential: '0',
    constraints: sys.constraints.map((row) => row.slice(0, Math.max(0, names.length - 1))),
  };
}

/** A custom system written in `form`, itself when it is in that form already. */
export function inForm(sys, form) {
  if (formOf(sys) === form) return copyCustom(sys);
  return form === 'general' ? toGeneral(sys) : toPaper(sys);
}

/**
 * The integrals the server may offer: in the paper's form, the latitude only for two
 * passengers and one constraint (it also needs a quadratic U, which the server checks); in
 * the general form, the energy, the constraint and the invariants by name, and the passenger
 * and driver energies where nhlab finds the paper's class (`CLASS_ONLY`).
 */
export function customIntegrals(sys) {
  if (isGeneral(sys)) {
    const invariants = Object.keys(sys.invariants ?? {});
    return sys.detect_class === false ? ['energy', 'constraint', ...invariants] : [...ALWAYS, ...invariants];
  }
  const latitude = sys.passenger.length === 2 && sys.constraints.length === 1;
  return latitude ? [...ALWAYS.slice(0, 3), 'latitude', 'constraint'] : [...ALWAYS];
}

/** The integrals a custom state starts with: those the system has in any case. */
export function defaultCustomIntegrals(sys) {
  return isGeneral(sys) ? ['energy', 'constraint', ...Object.keys(sys.invariants ?? {})] : [...ALWAYS];
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
