// The custom-system editor inside the form, in the paper's form (passenger and driver names,
// the potentials U and V_d, constraint rows with one entry per passenger) or the general one
// (coordinate names, the mass matrix M (massgrid.js), the potential V, constraint rows with
// one entry per coordinate, named invariants, whether to look for the paper's class); both
// with a name and parameters (add/remove). Filled from and read back into the object
// `"system"` takes in a request; "Form" writes the system shown in the other form. Every
// input sits in a field whose `data-path` is the API's path for it
// (`system.constraints[0][1]`, `system.mass[1][0]`, `system.parameters.k`,
// `system.invariants.H_y`), so the form shows a server error at its input.

import { cellRow, rowEntries, shapeRow } from './cells.js';
import { formOf, inForm } from '../data/custom.js';
import { customFromFields, parseNames } from '../data/customfields.js';
import { el, removeButton, textInput } from '../draw/dom.js';
import { MassGrid } from './massgrid.js';

const $ = (id) => document.getElementById(id);

// The lists of named values: parameters (numbers) and invariants (formulas).
const NAMED = {
  'custom-params': { what: 'parameter', path: 'system.parameters' },
  'custom-invariants': { what: 'invariant', path: 'system.invariants' },
};

export class Editor {
  /** `maxParameters`: the server's limit (`limits.formula_parameters`). */
  constructor({ maxParameters }) {
    this.maxParameters = maxParameters ?? 16;
    this.form = 'paper';
    this.mass = new MassGrid();
    for (const [box, button] of [['custom-params', 'custom-add-param'], ['custom-invariants', 'custom-add-invariant']]) {
      $(button).addEventListener('click', () => {
        this.#addNamed(box, '', box === 'custom-params' ? 0 : '');
        this.#buttons();
        this.#changed();
        $(box).lastElementChild?.querySelector('input')?.focus();
      });
    }
    $('custom-add-row').addEventListener('click', () => {
      $('custom-constraints').append(this.#row(this.#names().map(() => '0')));
      this.#renumber();
      this.#changed();
    });
    // New names: every row gets one entry per name (kept where it was, 0 added), M too.
    for (const id of ['custom-passenger', 'custom-coordinates']) $(id).addEventListener('change', () => this.#renumber());
    // The other form: the system shown, written in it.
    $('custom-form').addEventListener('change', () => this.fill(inForm(this.read([]), $('custom-form').value)));
  }

  /** Shows a custom system, in its form. */
  fill(sys) {
    this.form = formOf(sys);
    const general = this.form === 'general';
    $('custom-form').value = this.form;
    $('custom-editor').dataset.form = this.form;
    $('custom-name').value = sys.name ?? '';
    $('custom-passenger').value = general ? '' : sys.passenger.join(', ');
    $('custom-driver').value = general ? '' : sys.driver ?? '';
    $('custom-U').value = general ? '' : sys.passenger_potential ?? '';
    $('custom-Vd').value = general ? '' : sys.driver_potential ?? '';
    $('custom-coordinates').value = general ? sys.coordinates.join(', ') : '';
    $('custom-V').value = general ? sys.potential ?? '' : '';
    $('custom-detect').checked = !general || sys.detect_class !== false;
    for (const [box, values] of [['custom-params', sys.parameters], ['custom-invariants', general ? sys.invariants ?? {} : {}]]) {
      $(box).replaceChildren();
      for (const [name, value] of Object.entries(values)) this.#addNamed(box, name, value);
    }
    this.#buttons();
    this.mass.fill(general ? sys.mass : undefined, general ? sys.coordinates : []);
    $('custom-constraints').replaceChildren(...sys.constraints.map((row) => this.#row(row)));
    this.#renumber();
  }

  /** The custom system shown; fields that cannot be sent are pushed to `invalid`. */
  read(invalid) {
    const general = this.form === 'general';
    const { system, invalid: found } = customFromFields({
      name: $('custom-name').value,
      parameters: this.#pairs('custom-params'),
      constraints: [...$('custom-constraints').children].map(rowEntries),
      ...(general
        ? {
            coordinates: $('custom-coordinates').value,
            mass: this.mass.read(),
            potential: $('custom-V').value,
            invariants: this.#pairs('custom-invariants'),
            detect_class: $('custom-detect').checked,
          }
        : {
            passenger: $('custom-passenger').value,
            driver: $('custom-driver').value,
            passenger_potential: $('custom-U').value,
            driver_potential: $('custom-Vd').value,
          }),
    });
    invalid.push(...found);
    return system;
  }

  // The names the constraint rows have an entry for: the passengers, or the coordinates.
  #names() {
    return parseNames($(this.form === 'general' ? 'custom-coordinates' : 'custom-passenger').value);
  }

  #pairs(box) {
    return [...$(box).children].map((row) => [row.querySelector('.param-name').value, row.querySelector('.param-value').value]);
  }

  // A row `name = value`, ×; its path follows its name (`system.parameters.<name>`).
  #addNamed(box, name, value) {
    const { what, path } = NAMED[box];
    const row = el('div', 'field custom-param');
    const nameInput = textInput('param-name', name, `${what} name`);
    const valueInput = textInput(box === 'custom-params' ? 'param-value' : 'param-value formula', Number.isNaN(value) ? '' : String(value));
    if (box === 'custom-params') valueInput.inputMode = 'decimal';
    const named = () => {
      const n = nameInput.value.trim();
      row.dataset.path = n ? `${path}.${n}` : path;
      valueInput.setAttribute('aria-label', `${what === 'parameter' ? 'value' : 'formula'} of ${n || `the ${what}`}`);
    };
    nameInput.addEventListener('input', named);
    named();
    const remove = removeButton(`Remove this ${what}`, `remove this ${what}`, () => {
      row.remove();
      this.#buttons();
      this.#changed();
    });
    row.append(nameInput, el('span', 'eq', '='), valueInput, remove);
    $(box).append(row);
  }

  #row(entries) {
    return cellRow(entries, {
      what: 'constraint',
      onRemove: () => {
        this.#renumber();
        this.#changed();
      },
    });
  }

  // Paths and labels follow the rows' order and the names; a system keeps at least one
  // constraint, and at most one fewer than its passengers (its coordinates).
  #renumber() {
    const names = this.#names();
    const general = this.form === 'general';
    const rows = [...$('custom-constraints').children];
    rows.forEach((row, i) => {
      row.dataset.path = `system.constraints[${i}]`;
      shapeRow(row, names, `system.constraints[${i}]`, (name) => `constraint ${i + 1}, coefficient of the velocity of ${name}`, () => '0');
      row.querySelector(':scope > .icon').disabled = rows.length <= 1;
    });
    $('custom-add-row').disabled = rows.length >= Math.max(1, names.length - 1);
    $('custom-constraints-label').textContent = general ? 'Constraints A(q) q̇ = 0' : 'Constraints A(ζ) ẋ = 0';
    if (general) this.mass.rename(names);
  }

  #buttons() {
    $('custom-add-param').disabled = $('custom-params').children.length >= this.maxParameters;
  }

  // Rows and parameters added or removed: the form and the URL follow, as for an edit.
  #changed() {
    $('custom-editor').dispatchEvent(new Event('change', { bubbles: true }));
  }
}
