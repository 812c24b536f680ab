// What the page derives from the `GET /systems` catalog, by rule: it names no system and no
// method of its own. The default methods are the catalog's `default_methods` (the paper's
// five), the paper's experiments its `paper_scenes`; the integrals a paper figure shows, the
// default running-mean window, a system's short name and the Paper view's figures follow
// from the systems' integrals, presets and names; the methods that apply to a system and
// what it is (in the paper's class or not) from its `methods` and `paper_class`; the method
// given as a tableau and a constraint (PRK) from the `tableaux` it may name, each with the
// constraints it takes, their order and symmetry. Pure functions, so node tests cover them.

import { INTEGRAL_NAME, INTEGRAL_SHORT } from './verdicts.js';

export function findSystem(catalog, id) {
  return catalog.systems.find((s) => s.id === id);
}

export function findPreset(system, id) {
  return system?.presets?.find((p) => p.id === id);
}

export function findMethod(catalog, id) {
  return catalog.methods.find((m) => m.id === id);
}

/** The methods (catalog entries) that apply to a system: a built-in's `methods`; every method
 *  for a custom system (the server says which do not apply when it runs). */
export function methodsFor(catalog, system) {
  const ids = findSystem(catalog, system)?.methods;
  return Array.isArray(ids) ? catalog.methods.filter((m) => ids.includes(m.id)) : catalog.methods;
}

/** `methods` (`{id, …}`) without those that do not apply to `system`. */
export function applicable(catalog, system, methods) {
  const ids = new Set(methodsFor(catalog, system).map((m) => m.id));
  return methods.filter((m) => ids.has(m.id));
}

/** What a system is, as a sentence, from a `paper_class` (a built-in's or a scene's): "In the
 *  paper's class, driver y." or "Outside the paper's class: <why not>.", with `remark` after
 *  "class"; '' without one. */
export function paperClassLine(paperClass, remark = '') {
  if (!paperClass) return '';
  const { member, driver, why_not: why } = paperClass;
  const line = member ? `In the paper’s class${remark}${driver ? `, driver ${driver}` : ''}` : `Outside the paper’s class${remark}${why ? `: ${why}` : ''}`;
  return `${line.replace(/\.$/, '')}.`;
}

/**
 * The methods a state starts with, as `{id, params}`: the catalog's `default_methods` (whose
 * parameter values come inline, `{"id": …, "alpha": 0.4, "label": …}`, or as a `params`
 * object), each with the parameters its method lists. Methods the catalog does not list are
 * left out; without `default_methods`, every method with its defaults.
 */
export function defaultMethods(catalog) {
  const listed = catalog.default_methods;
  if (!Array.isArray(listed) || listed.length === 0) {
    return catalog.methods.map((m) => ({ id: m.id, params: Object.fromEntries((m.params ?? []).map((p) => [p.name, p.default])) }));
  }
  const out = [];
  for (const view of listed) {
    const info = findMethod(catalog, view.id);
    if (!info) continue;
    const values = view.params && typeof view.params === 'object' ? view.params : view;
    const params = {};
    for (const p of info.params ?? []) {
      if (typeof values[p.name] === 'number') params[p.name] = values[p.name];
    }
    out.push({ id: view.id, params });
  }
  return out;
}

/**
 * The integrals a paper figure shows for a system: a system with a hidden integral (the
 * latitude) is shown by its split energies and that integral — every integral but the total
 * energy and the constraint residual; any other by its total energy.
 */
export function figureIntegrals(system) {
  const integrals = system?.integrals ?? [];
  if (integrals.includes('latitude')) return integrals.filter((i) => i !== 'energy' && i !== 'constraint');
  if (integrals.includes('energy')) return ['energy'];
  return integrals.filter((i) => i !== 'constraint').slice(0, 1);
}

/**
 * The default running-mean window (time units) for a final time: 3 % of the decade of t_end,
 * i.e. 3·10^(k−2) for t_end in [10^k, 10^(k+1)). It gives the paper's windows for the paper's
 * presets: 3 for t_end = 100, 30 for t_end = 3000 (and 30 for 1000). Without a usable t_end,
 * the window of t_end = 100.
 */
export function defaultWindow(tEnd) {
  const t = Number.isFinite(tEnd) && tEnd > 0 ? tEnd : 100;
  const decade = Math.floor(Math.log10(t) + 1e-9);
  return Number((3 * 10 ** (decade - 2)).toPrecision(1));
}

/** The paper's experiments: `paper_scenes` the catalog can resolve, each with its system,
 *  preset, button label and the integrals its figures show. */
export function paperExperiments(catalog) {
  const out = [];
  for (const scene of catalog.paper_scenes ?? []) {
    const system = findSystem(catalog, scene.system);
    const preset = findPreset(system, scene.preset);
    if (!preset) continue;
    out.push({
      system: system.id,
      preset: preset.id,
      label: presetLabel(preset),
      integrals: figureIntegrals(system),
      window: defaultWindow(preset.t_end),
    });
  }
  return out;
}

/** A preset's label without the "Paper: " the paper's presets carry. */
export function presetLabel(preset) {
  return (preset?.label ?? preset?.id ?? '').replace(/^Paper:\s*/, '');
}

/** A system's short name: its name up to the first comma or parenthesis ("CVT, pendulum
 *  driver" → "CVT"), else its id. */
export function systemShortName(system) {
  const short = (system?.name ?? '').split(/\s*[,(]/)[0].trim();
  return short || system?.id || '';
}

/**
 * Panel titles for labels shown side by side: each label without the comma-separated parts
 * every label starts with ("knife edge, ε = 0" and "knife edge, ε = 0.1" → "ε = 0", "ε = 0.1").
 */
export function panelTitles(labels) {
  const parts = labels.map((l) => l.split(/,\s*/));
  let common = 0;
  while (
    parts.length > 1 &&
    parts.every((p) => p.length > common + 1 && p[common] === parts[0][common])
  ) {
    common++;
  }
  return parts.map((p) => p.slice(common).join(', '));
}

/** The remark a figure title adds for an integral. */
const INTEGRAL_REMARK = { latitude: ' (hidden integral, at the section crossings)' };

/**
 * The Paper view's figures: for each system of the paper's experiments (in order of first
 * appearance), one figure per integral it shows, with a panel per experiment of that system.
 * Each panel carries its running-mean window (the preset's default).
 */
export function paperFigures(catalog) {
  const bySystem = new Map();
  for (const x of paperExperiments(catalog)) {
    if (!bySystem.has(x.system)) bySystem.set(x.system, []);
    bySystem.get(x.system).push(x);
  }
  const figures = [];
  for (const [systemId, experiments] of bySystem) {
    const system = findSystem(catalog, systemId);
    const titles = panelTitles(experiments.map((x) => x.label));
    const panels = experiments.map((x, i) => ({ system: systemId, preset: x.preset, title: titles[i], window: x.window }));
    for (const integral of figureIntegrals(system)) {
      const name = INTEGRAL_NAME[integral] ?? integral;
      const symbol = INTEGRAL_SHORT[integral];
      const error = symbol ? ` |${symbol} − ${symbol}(0)|` : '';
      figures.push({
        id: `${systemId}-${integral}`,
        system: systemId,
        title: `${systemShortName(system)}: ${name} error${error}${INTEGRAL_REMARK[integral] ?? ''}`,
        integral,
        panels,
      });
    }
  }
  return figures;
}

/** The scenes to stream for the figures: each scene once, with the integrals its panels show. */
export function figureScenes(figures) {
  const scenes = new Map();
  for (const f of figures) {
    for (const p of f.panels) {
      const key = `${p.system}/${p.preset}`;
      if (!scenes.has(key)) scenes.set(key, { system: p.system, preset: p.preset, integrals: [] });
      const s = scenes.get(key);
      if (!s.integrals.includes(f.integral)) s.integrals.push(f.integral);
    }
  }
  return [...scenes.values()];
}

// What the method given as a tableau runs without one (the server's defaults, docs/api.md).
const DEFAULT_TABLEAU = 'gauss2';
export const DEFAULT_CONSTRAINT = 'stage';

/** The id of the method given as a tableau and a constraint: the one GET /systems marks
 *  `by_tableau`, where the catalog has tableaux for it. */
export function tableauMethod(catalog) {
  if (!catalog.tableaux?.length) return undefined;
  return catalog.methods.find((m) => m.by_tableau)?.id;
}

/** Whether the method `id` is given as a tableau and a constraint. */
export function takesTableau(catalog, id) {
  const method = tableauMethod(catalog);
  return method !== undefined && method === id;
}

export function findTableau(catalog, id) {
  return catalog.tableaux?.find((t) => t.id === id);
}

/**
 * A PRK method's stored tableau and constraint as the catalog can run them, with `entry`, the
 * tableau's `constraints` entry for that constraint ({id, order, symmetric, label}). An
 * unknown or missing tableau falls back to gauss2 (else the first listed), a constraint the
 * tableau does not take to `stage` (else its first); callers compare to say so. Without
 * `tableaux` in the catalog the choice is kept as given, with no entry.
 */
export function tableauChoice(catalog, tableau, constraint) {
  const t = findTableau(catalog, tableau) ?? findTableau(catalog, DEFAULT_TABLEAU) ?? catalog.tableaux?.[0];
  if (!t) return { tableau: tableau ?? DEFAULT_TABLEAU, constraint: constraint ?? DEFAULT_CONSTRAINT, entry: undefined };
  const takes = (id) => t.constraints.some((c) => c.id === id);
  const c = takes(constraint) ? constraint : takes(DEFAULT_CONSTRAINT) ? DEFAULT_CONSTRAINT : t.constraints[0]?.id;
  return { tableau: t.id, constraint: c, entry: t.constraints.find((x) => x.id === c) };
}

/** Whether `info`'s method with `params` may be composed (GET /systems' `symmetric_at`), and
 *  its order alone. A PRK method's both come from `constraint`, its tableau's entry for its
 *  constraint (`tableauChoice(…).entry`): the method's own `composable` is its default's. */
export function composableAt(info, params, constraint) {
  if (constraint) return { composable: constraint.symmetric === true, order: constraint.order };
  const at = info.symmetric_at;
  if (!info.composable) return { composable: false, order: info.order };
  if (!at) return { composable: true, order: info.order };
  const here = params[at.param] ?? info.params?.find((p) => p.name === at.param)?.default;
  return here === at.value ? { composable: true, order: info.order } : { composable: false, order: at.order_elsewhere };
}
