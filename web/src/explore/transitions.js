// The Explore form's moves from one state to the next, pure (node tests cover them): a new
// system or preset, the formula editor opened on the system shown or started from a
// built-in (in the paper's form or the general one), a paper experiment, and a scene opened
// from the Scorecard or the Map. Each takes the catalog (GET /systems) and the form's
// current state and returns the state to fill in. Methods that do not apply to the new
// system (one made for the paper's class alone, on a system outside it) are left out.

import { applicable, defaultWindow, findSystem } from '../data/catalog.js';
import { coordinateNames, customFrom, customIntegrals, isCustom } from '../data/custom.js';
import { defaultCustomState, defaultState } from '../data/state.js';

/** A new built-in system: its first preset, defaults for integrals and window; the methods
 *  that apply to it and the display stay. */
export function systemSwitched(catalog, current, system) {
  const next = defaultState(catalog, system);
  const kept = applicable(catalog, system, current.methods);
  next.methods = kept.length ? kept : next.methods;
  next.stat = current.stat;
  next.smooth = current.smooth;
  return next;
}

/** A new preset refills what presets define; methods, integrals and display stay (the window
 *  follows the new final time while it is the old one's default). */
export function presetSwitched(catalog, current) {
  const next = defaultState(catalog, current.system, current.preset);
  const out = { ...current };
  if (current.window === defaultWindow(current.t_end)) out.window = next.window;
  return Object.assign(out, { params: next.params, q: next.q, v: next.v, step: next.step, t_end: next.t_end });
}

/** The formula editor on the system of `current`, written as formulas at its parameter
 *  values (in `form`, else in the paper's form where it has one); its initial state (where
 *  its size fits the formulas: else the first preset's that does), times, methods and
 *  display stay, and the integrals it offers. */
export function customized(catalog, current, form) {
  const sys = customFrom(catalog, current.system, current.params, form);
  const offered = customIntegrals(sys);
  const next = defaultCustomState(catalog, sys);
  const integrals = current.integrals.filter((i) => offered.includes(i));
  const n = coordinateNames(sys).length;
  const fits = (p) => p.q.length === n && p.v.length === n;
  const start = fits(current) ? current : findSystem(catalog, current.system)?.presets?.find(fits) ?? { q: [], v: [] };
  return Object.assign(next, {
    q: [...start.q],
    v: [...start.v],
    step: current.step,
    t_end: current.t_end,
    points: current.points,
    methods: current.methods.length ? current.methods : next.methods,
    integrals: integrals.length ? integrals : next.integrals,
    stat: current.stat,
    smooth: current.smooth,
    window: current.window,
  });
}

/** "Start from" a built-in: its formulas in `form` at its first preset's parameters, that
 *  preset's initial state and times; the methods and display stay. */
export function startedFrom(catalog, current, system, form) {
  const base = defaultState(catalog, system);
  return customized(catalog, { ...base, methods: current.methods, points: current.points, stat: current.stat, smooth: current.smooth }, form);
}

/** A paper experiment: its scene at its preset, with the integrals its figures show. */
export function experiment(catalog, x) {
  const state = defaultState(catalog, x.system, x.preset);
  state.integrals = [...x.integrals];
  state.smooth = true;
  return state;
}

/** A scorecard cell (its scene, with the scorecard's methods) or a map cell (its /simulate
 *  body, with its one method); what the scene leaves out comes from its preset. Methods that
 *  do not apply to its system are left out. */
export function sceneOpened(catalog, scene, methods) {
  const custom = isCustom(scene.system);
  const state = custom ? defaultCustomState(catalog, scene.system) : defaultState(catalog, scene.system, scene.preset);
  return Object.assign(state, {
    params: custom ? {} : { ...state.params, ...scene.params },
    q: scene.q ? [...scene.q] : state.q,
    v: scene.v ? [...scene.v] : state.v,
    step: scene.step ?? state.step,
    t_end: scene.t_end ?? state.t_end,
    points: scene.points ?? state.points,
    integrals: scene.integrals ? [...scene.integrals] : state.integrals,
    window: defaultWindow(scene.t_end ?? state.t_end),
    smooth: true,
    methods: applicable(catalog, scene.system, methods).map((m) => ({
      id: m.id,
      params: Object.fromEntries(Object.entries(m).filter(([k]) => !['id', 'label', 'composition', 'tableau', 'constraint'].includes(k))),
      // A PRK method's stored tableau and constraint (a tableau given in full is not one the
      // form offers: the form shows the default there).
      ...(typeof m.tableau === 'string' ? { tableau: m.tableau } : {}),
      ...(m.constraint ? { constraint: m.constraint } : {}),
      ...(m.composition ? { composition: m.composition } : {}),
    })),
  });
}
