// The form: built from the /systems catalog, filled from a state, read back into one, and
// showing errors next to the field an API error's `path` names (`params.epsilon`,
// `methods[1].alpha`, `q[2]`, `system.constraints[0][1]`, …). Every field carries a
// `data-path` for that lookup. "Custom system" in the system select shows the editor
// (editor.js) in place of the preset and parameters. A built-in is shown with whether it is
// in the paper's class, and offers the methods that apply to it. A PRK method's row picks a
// stored tableau and one of the constraints that tableau takes; its order and whether it may
// be composed are that pair's (GET /systems' `tableaux`).

import { composableAt, defaultWindow, findPreset, findSystem, findTableau, methodsFor, paperClassLine, tableauChoice, takesTableau } from '../data/catalog.js';
import { CLASS_ONLY, CUSTOM, coordinateNames, customIntegrals, defaultCustomIntegrals, isCustom, isGeneral, startingPoints } from '../data/custom.js';
import { Editor } from './editor.js';
import { parseList } from '../data/state.js';
import { methodStyle } from '../draw/palette.js';
import { swatch } from '../draw/markers.js';
import { el, option, removeButton } from '../draw/dom.js';
import { humanLabel, symbol } from '../data/labels.js';
import { INTEGRAL_NAME } from '../data/verdicts.js';

// What the form says of a custom system, per form.
const CUSTOM_TEXT = {
  paper: ['A system of your own, as formulas: passengers x with potential U, a driver ζ with potential V_d, and A(ζ) ẋ = 0.', 'In the paper’s class by its form.'],
  general: ['A system of your own, as formulas: coordinates q, a constant mass matrix M, a potential V(q), constraints A(q) q̇ = 0 and named invariants.', 'Whether it is in the paper’s class is found when it runs.'],
};

const $ = (id) => document.getElementById(id);

export class Form {
  constructor(catalog) {
    this.catalog = catalog;
    this.el = $('form');
    this.offered = [];
    this.errors = 0;
    $('system').replaceChildren(...catalog.systems.map((s) => option(s.id, s.name)), option(CUSTOM, 'Custom system (formulas)…'));
    // "Start from": every built-in in the general form, those of the paper's class in its form.
    const starts = startingPoints(catalog);
    const group = (label, form, systems) => {
      const g = el('optgroup');
      g.label = label;
      g.append(...systems.map((s) => option(`${form}:${s.id}`, s.name)));
      return g;
    };
    $('custom-start').replaceChildren(
      option('', 'Pick a built-in system…'),
      group('In the paper’s form', 'paper', starts.paper),
      group('In the general form', 'general', starts.general),
    );
    this.editor = new Editor({ maxParameters: catalog.limits?.formula_parameters });
    // Editing the custom system's shape changes the integrals it may have and q's size; an
    // invariant just named is measured.
    $('custom-editor').addEventListener('change', () => {
      if ($('system').value !== CUSTOM) return;
      const sys = this.editor.read([]);
      const added = defaultCustomIntegrals(sys).filter((i) => !this.offered.includes(i));
      this.#custom(sys, [...this.#checkedIntegrals(), ...added]);
    });
  }

  /** Shows a state in the form. */
  fill(state) {
    const custom = isCustom(state.system);
    this.shown = custom ? CUSTOM : state.system;
    $('custom-editor').hidden = !custom;
    $('preset').closest('.field').hidden = custom;
    if (custom) {
      $('system').value = CUSTOM;
      $('custom-start').value = '';
      $('preset').replaceChildren(option('', 'None'));
      this.#params({ params: [] }, {});
      this.editor.fill(state.system);
      this.#custom(state.system, state.integrals);
      this.#methodChoice(this.catalog.methods);
    } else {
      const system = findSystem(this.catalog, state.system);
      $('system').value = system.id;
      $('system-description').textContent = system.description ?? '';
      // Found at its default parameters; a run reports the scene's own.
      const defaults = system.params.length ? ' (at its defaults)' : '';
      $('system-class').textContent = paperClassLine(system.paper_class, defaults);
      $('system-class').dataset.member = String(Boolean(system.paper_class?.member));
      $('preset').replaceChildren(
        ...(system.presets ?? []).map((p) => option(p.id, p.label)),
        option('', 'None (system defaults)'),
      );
      $('preset').value = state.preset;
      this.#params(system, state.params);
      // An empty step or final time runs the preset's: the placeholders show its values.
      const preset = findPreset(system, state.preset);
      const shown = (v) => (Number.isFinite(v) ? `${Number(v.toPrecision(6))} (preset)` : '');
      this.#placeholders(sizeHint(system, preset), shown(preset?.step), shown(preset?.t_end));
      this.#integrals(system.integrals, state.integrals);
      this.#methodChoice(methodsFor(this.catalog, system.id));
    }
    $('q').value = state.q.map(String).join(', ');
    $('v').value = state.v.map(String).join(', ');
    setNumber($('step'), state.step);
    setNumber($('t_end'), state.t_end);
    setNumber($('points'), state.points);
    $('methods').replaceChildren();
    for (const m of state.methods) this.addMethod(m.id, m.params, m.composition, m);
    $('stat').value = state.stat;
    $('smooth').checked = state.smooth;
    setNumber($('window'), state.window);
  }

  /** Adds a method row (checked), with an input per method parameter, for a PRK method a
   *  tableau and a constraint select (set to `tableau` and `constraint`, else the defaults)
   *  and, for a symmetric method, a composition picker. */
  addMethod(id, params = {}, composition = '', { tableau, constraint } = {}) {
    const info = this.catalog.methods.find((m) => m.id === id);
    if (!info) return;
    const row = el('div', 'method-row field');
    const box = el('input');
    box.type = 'checkbox';
    box.checked = true;
    box.className = 'method-on';
    box.dataset.id = id;
    box.setAttribute('aria-label', `use ${info.name}`);
    const swatch = el('span', 'swatch');
    const name = el('span', 'method-name', humanLabel(info.name));
    name.title = [info.name, info.order ? `order ${info.order}` : '', info.reference].filter(Boolean).join(' · ');
    row.append(box, swatch, name);
    for (const p of info.params ?? []) {
      const wrap = el('label', 'method-param');
      const input = el('input');
      input.type = 'number';
      input.step = 'any';
      input.dataset.param = p.name;
      if (Number.isFinite(p.min)) input.min = p.min;
      if (Number.isFinite(p.max)) input.max = p.max;
      setNumber(input, params[p.name] ?? p.default);
      input.title = p.description ?? p.name;
      wrap.append(el('span', 'method-param-name', `${symbol(p.name)} =`), input);
      row.append(wrap);
    }
    const byTableau = takesTableau(this.catalog, id);
    if (byTableau) row.append(...this.#tableauPickers(info, tableauChoice(this.catalog, tableau, constraint)));
    // A PRK method may be composed with some tableaux and constraints, not with its default.
    const picker = (info.composable || byTableau) && this.catalog.compositions?.length ? this.#compositionPicker(info, composition) : null;
    if (picker) row.append(picker);
    // Offered only where the method as configured is symmetric (DLA^α at α = 0.5, a PRK's
    // tableau with its constraint), with the order it reaches; kept in step with its
    // parameters and its tableau.
    const sync = () => offerCompositions(picker, info, paramsOf(row), name, this.#entryOf(row));
    if (picker || byTableau) {
      for (const input of row.querySelectorAll('input[data-param]')) input.addEventListener('input', sync);
      for (const select of row.querySelectorAll('select[data-tableau], select[data-constraint]')) select.addEventListener('change', sync);
      sync();
    }
    const remove = removeButton('Remove this method', `remove ${info.name}`, () => {
      row.remove();
      this.el.dispatchEvent(new Event('change', { bubbles: true }));
    });
    row.append(remove);
    $('methods').append(row);
    this.#numberRows();
  }

  // A composition of a symmetric method's steps raises its order (GET /systems lists them).
  // Its first option names the method's own order, set by offerCompositions.
  #compositionPicker(info, chosen) {
    const wrap = el('label', 'method-param method-composition');
    const select = el('select');
    select.dataset.composition = '';
    select.title = 'Take the method as a symmetric composition of its steps (higher order, same structure)';
    select.setAttribute('aria-label', `composition of ${info.name}`);
    select.append(option('', 'order 2'));
    // Some methods' compositions stop below the scheme's order (measured; GET /systems says so).
    // offerCompositions writes each option's text with the order the method reaches alone.
    const limit = info.composed_order_limit ?? Infinity;
    for (const c of this.catalog.compositions) {
      const o = option(c.id, '');
      Object.assign(o.dataset, { order: Math.min(c.order, limit), stages: c.stages });
      select.append(o);
    }
    select.value = this.catalog.compositions.some((c) => c.id === chosen) ? chosen : '';
    wrap.append(select);
    return wrap;
  }

  // A PRK method's tableau select (every stored tableau, by id and order) and its constraint
  // select (those the tableau takes, by id and the order they give); choosing a tableau
  // offers its constraints, keeping the one chosen where the tableau takes it.
  #tableauPickers(info, choice) {
    const pick = (what, title) => {
      const wrap = el('label', `method-param method-${what}`);
      const select = el('select');
      select.dataset[what] = '';
      select.title = title;
      select.setAttribute('aria-label', `${what} of ${info.name}`);
      wrap.append(el('span', 'method-param-name', what), select);
      return [wrap, select];
    };
    const [tableauWrap, tableau] = pick('tableau', 'A stored tableau (GET /systems lists them), with its classical order');
    const [constraintWrap, constraint] = pick('constraint', 'How the constraint is imposed: at the stages, at the step’s end or at the chord’s midpoint; the order the method then reaches');
    tableau.append(...(this.catalog.tableaux ?? []).map((t) => option(t.id, `${t.id} (order ${t.order})`)));
    tableau.value = choice.tableau;
    const offer = (chosen) => {
      const t = findTableau(this.catalog, tableau.value);
      constraint.replaceChildren(...(t?.constraints ?? []).map((c) => option(c.id, `${c.id} (order ${c.order})`)));
      constraint.value = tableauChoice(this.catalog, tableau.value, chosen).constraint;
    };
    offer(choice.constraint);
    tableau.addEventListener('change', () => offer(constraint.value));
    return [tableauWrap, constraintWrap];
  }

  // The constraint entry of a PRK row's tableau and constraint (undefined for other methods).
  #entryOf(row) {
    const tableau = row.querySelector('select[data-tableau]');
    return tableau ? tableauChoice(this.catalog, tableau.value, row.querySelector('select[data-constraint]').value).entry : undefined;
  }

  // The methods the "Add method" select offers: those that apply to the system.
  #methodChoice(methods) {
    $('add-method-id').replaceChildren(...methods.map((m) => option(m.id, humanLabel(m.name))));
  }

  // A custom system's description, integrals and the sizes of q and q̇ (its names, the
  // driver last in the paper's form); the server's defaults for an empty step and final time.
  // In the general form the passenger and driver energies exist only where the paper's class
  // is found, and say so.
  #custom(sys, checked) {
    const names = coordinateNames(sys);
    const [description, what] = CUSTOM_TEXT[isGeneral(sys) ? 'general' : 'paper'];
    $('system-description').textContent = description;
    $('system-class').textContent = what;
    delete $('system-class').dataset.member;
    this.#placeholders(`${names.length} numbers: ${names.join(', ')}`, '0.1', '100');
    const classOnly = isGeneral(sys) ? CLASS_ONLY : [];
    this.#integrals(customIntegrals(sys), checked, (id) => (classOnly.includes(id) ? ' (in the paper’s class only)' : ''));
  }

  #placeholders(q, step, tEnd) {
    $('q').placeholder = q;
    $('v').placeholder = q;
    $('step').placeholder = step;
    $('t_end').placeholder = tEnd;
  }

  // `note(id)`: what to add to an integral's name.
  #integrals(offered, checked, note = () => '') {
    this.offered = offered;
    $('integrals').replaceChildren(
      ...offered.map((id) => {
        const label = el('label', 'check');
        const box = el('input');
        box.type = 'checkbox';
        box.name = 'integral';
        box.value = id;
        box.checked = checked.includes(id);
        // The integral's name, its API id on hover (what a link or a script writes).
        label.title = id;
        label.append(box, document.createTextNode(` ${INTEGRAL_NAME[id] ?? id}${note(id)}`));
        return label;
      }),
    );
  }

  #checkedIntegrals() {
    return [...$('integrals').querySelectorAll('input:checked')].map((b) => b.value);
  }

  /** Reads the form into a state; `invalid` lists fields that do not parse ({path, message}).
   *  `as`: read it as that system select value (the one shown before a switch, `shown`). */
  read({ as } = {}) {
    const invalid = [];
    const number = (input, path) => {
      if (input.value.trim() === '') return null;
      const v = Number(input.value);
      if (!Number.isFinite(v)) invalid.push({ path, message: 'not a number' });
      return v;
    };
    const custom = (as ?? $('system').value) === CUSTOM;
    const system = custom ? null : findSystem(this.catalog, as ?? $('system').value);
    const params = {};
    for (const input of custom ? [] : $('params').querySelectorAll('input')) {
      const v = number(input, `params.${input.name}`);
      if (v !== null) params[input.name] = v;
    }
    const list = (id) => {
      const values = parseList($(id).value);
      if (values.some((v) => !Number.isFinite(v))) invalid.push({ path: id, message: 'comma-separated numbers, please' });
      return values;
    };
    const methods = [];
    for (const row of $('methods').querySelectorAll('.method-row')) {
      if (row.querySelector('.method-on').checked) methods.push(rowMethod(row, number));
    }
    if (methods.length === 0) invalid.push({ path: 'methods', message: 'choose at least one method' });
    const integrals = this.#checkedIntegrals();
    if (integrals.length === 0) invalid.push({ path: 'integrals', message: 'choose at least one integral' });
    const t_end = number($('t_end'), 't_end');
    const state = {
      system: custom ? this.editor.read(invalid) : system.id,
      preset: custom ? '' : $('preset').value,
      params,
      q: list('q'),
      v: list('v'),
      step: number($('step'), 'step'),
      t_end,
      points: number($('points'), 'points'),
      methods,
      integrals,
      stat: $('stat').value,
      smooth: $('smooth').checked,
      // An empty window: the default for the final time (the preset's when that is empty too).
      window: number($('window'), 'window') ?? defaultWindow(t_end ?? findPreset(system, $('preset').value)?.t_end),
      run: false,
    };
    return { state, invalid };
  }

  /** Shows `message` next to the field `path` names (or its closest named ancestor). */
  showError(path, message) {
    const target = this.#fieldFor(path ?? '');
    const p = el('p', 'field-error', message);
    p.setAttribute('role', 'alert');
    if (target) {
      target.classList.add('invalid');
      // The control itself says it is invalid, and which message describes it.
      p.id = `error-${++this.errors}`;
      const control = target.matches('input, select, textarea') ? target : target.querySelector('input, select, textarea');
      if (control) {
        control.setAttribute('aria-invalid', 'true');
        control.setAttribute('aria-describedby', p.id);
      }
      // A method parameter's or a constraint entry's message goes under its row, not inside
      // the inline label.
      const inline = target.classList.contains('method-param') || target.classList.contains('custom-cell');
      (inline ? target.closest('.method-row, .custom-row') : target).append(p);
      target.scrollIntoView?.({ block: 'nearest' });
      return true;
    }
    return false;
  }

  clearErrors() {
    for (const e of this.el.querySelectorAll('.field-error')) e.remove();
    for (const e of this.el.querySelectorAll('.invalid')) e.classList.remove('invalid');
    for (const e of this.el.querySelectorAll('[aria-invalid]')) {
      e.removeAttribute('aria-invalid');
      e.removeAttribute('aria-describedby');
    }
  }

  /** Brings the first invalid field into view and focuses its control: where the eye and the
   *  keyboard should go after an error. Returns whether there was one. */
  focusFirstError() {
    const first = this.el.querySelector('[aria-invalid="true"]') ?? this.el.querySelector('.invalid');
    if (!first) return false;
    first.scrollIntoView?.({ block: 'center' });
    first.focus?.({ preventScroll: true });
    return true;
  }

  #fieldFor(path) {
    // methods[1].alpha → methods[1].alpha, methods[1], methods; q[2] → q; params.epsilon → params
    let p = path;
    while (p) {
      const found = this.el.querySelector(`[data-path="${CSS.escape(p)}"]`);
      if (found) return found;
      const cut = Math.max(p.lastIndexOf('.'), p.lastIndexOf('['));
      if (cut <= 0) break;
      p = p.slice(0, cut);
    }
    return null;
  }

  // Rows are numbered as the request numbers methods: enabled rows only, in order. Swatches
  // show the line and marker each enabled method will be drawn with.
  #numberRows() {
    let i = 0;
    for (const row of $('methods').querySelectorAll('.method-row')) {
      const on = row.querySelector('.method-on').checked;
      row.classList.toggle('off', !on);
      this.#swatch(row, on);
      if (on) {
        row.dataset.path = `methods[${i}]`;
        for (const input of row.querySelectorAll('input[data-param]')) {
          input.closest('.method-param').dataset.path = `methods[${i}].${input.dataset.param}`;
        }
        for (const what of ['composition', 'tableau', 'constraint']) {
          const picker = row.querySelector(`.method-${what}`);
          if (picker) picker.dataset.path = `methods[${i}].${what}`;
        }
        i++;
      } else {
        delete row.dataset.path;
      }
    }
  }

  #swatch(row, on) {
    const params = {};
    for (const input of row.querySelectorAll('input[data-param]')) if (input.value !== '') params[input.dataset.param] = Number(input.value);
    const composition = row.querySelector('select[data-composition]')?.value;
    const style = methodStyle(this.catalog, { id: row.querySelector('.method-on').dataset.id, params, composition });
    const box = row.querySelector('.swatch');
    if (box.dataset.key === `${on}|${JSON.stringify(style)}`) return;
    box.dataset.key = `${on}|${JSON.stringify(style)}`;
    box.replaceChildren(...(on ? [swatch(style, { width: 22 })] : []));
  }

  /** Call after any change to the method rows. */
  renumber() {
    this.#numberRows();
  }

  #params(system, values) {
    const fields = system.params.map((p) => {
      const field = el('div', 'field');
      field.dataset.path = `params.${p.name}`;
      const id = `param-${p.name}`;
      const label = el('label', '', paramSymbol(p.name));
      label.htmlFor = id;
      const input = el('input');
      input.type = 'number';
      input.step = 'any';
      input.id = id;
      input.name = p.name;
      if (Number.isFinite(p.min)) input.min = p.min;
      if (Number.isFinite(p.max)) input.max = p.max;
      setNumber(input, values[p.name] ?? p.default);
      const range = Number.isFinite(p.min) || Number.isFinite(p.max) ? ` Allowed: ${interval(p)}.` : '';
      field.append(label, input, el('p', 'hint', `${p.description ?? ''}.${range}`.replace(/\.\./g, '.')));
      return field;
    });
    $('params').replaceChildren(...fields);
    $('params-fieldset').hidden = fields.length === 0;
  }
}

// A parameter named after a Greek letter is shown as the letter.
function paramSymbol(name) {
  return symbol(name) === name ? name : `${symbol(name)} (${name})`;
}

// What q(0) and q̇(0) take: the preset's size where it has one (a parameter may change the
// number of coordinates), with the coordinates' names where they are that many.
function sizeHint(system, preset) {
  const names = system.general?.coordinates ?? [];
  const n = preset?.q?.length ?? system.dof;
  return names.length === n ? `${n} numbers: ${names.join(', ')}` : `${n} numbers`;
}

// (-1, 1) for open bounds, [-10, 10] for closed ones.
function interval(p) {
  return `${p.min_open ? '(' : '['}${fmt(p.min)}, ${fmt(p.max)}${p.max_open ? ')' : ']'}`;
}

function fmt(v) {
  return Number.isFinite(v) ? String(v) : v > 0 ? '∞' : '−∞';
}

function setNumber(input, v) {
  input.value = v === null || v === undefined || Number.isNaN(v) ? '' : String(v);
}

/**
 * The method a form row holds, as a state keeps it: `{id, params}`, with a PRK method's
 * tableau and constraint and the composition where one is chosen. `number(input, path)` reads
 * a parameter's input (null when empty), noting one that does not parse.
 */
export function rowMethod(row, number) {
  const method = { id: row.querySelector('.method-on').dataset.id, params: {} };
  for (const input of row.querySelectorAll('input[data-param]')) {
    const v = number(input, `${row.dataset.path}.${input.dataset.param}`);
    if (v !== null) method.params[input.dataset.param] = v;
  }
  const tableau = row.querySelector('select[data-tableau]')?.value;
  if (tableau) Object.assign(method, { tableau, constraint: row.querySelector('select[data-constraint]').value });
  const composition = row.querySelector('select[data-composition]')?.value;
  if (composition) method.composition = composition;
  return method;
}

/** A method row's parameter values, by name, as its inputs hold them. */
function paramsOf(row) {
  return Object.fromEntries([...row.querySelectorAll('input[data-param]')].map((i) => [i.dataset.param, Number(i.value)]));
}

/**
 * The composition picker of a method row (if it has one), in step with its parameters and a
 * PRK method's tableau and constraint (`entry`, the tableau's entry for the constraint):
 * shown only where the method as configured is symmetric (`composableAt`), its first option
 * the order the method reaches alone, each composition's the order it reaches (the scheme's,
 * never below the method's own, as the server counts it); a choice made where it no longer
 * applies is dropped. The method's name says the order too (a PRK's with its label,
 * `PRK[gauss3]`).
 */
function offerCompositions(picker, info, params, name, entry) {
  const { composable, order } = composableAt(info, params, entry);
  if (picker) {
    const select = picker.querySelector('select');
    picker.hidden = !composable;
    if (!composable) select.value = '';
    select.options[0].textContent = `order ${order}`;
    for (const o of [...select.options].slice(1)) {
      o.textContent = `∘${o.value} (order ${Math.max(order, Number(o.dataset.order))}, ${o.dataset.stages} stages)`;
    }
  }
  const why = entry ? 'not symmetric with this tableau and constraint' : 'not symmetric at these parameters';
  name.title = [entry?.label ?? info.name, `order ${order}`, composable ? '' : `${why}: no composition`, info.reference].filter(Boolean).join(' · ');
}
