// The custom-system editor inside the form: name, passenger and driver names, parameters
// (add/remove), the potentials U and V_d and the constraint rows (add/remove, one entry per
// passenger). Filled from and read back into the object `"system"` takes in a request. Every
// input sits in a field whose `data-path` is the API's path for it (`system.constraints[0][1]`,
// `system.parameters.k`), so the form shows a server error at its input.

import { customFromFields, parseNames } from './custom.js';
import { el } from './dom.js';

const $ = (id) => document.getElementById(id);

export class Editor {
  /** `maxParameters`: the server's limit (`limits.formula_parameters`). */
  constructor({ maxParameters }) {
    this.maxParameters = maxParameters ?? 16;
    $('custom-add-param').addEventListener('click', () => {
      this.#addParam('', 0);
      this.#buttons();
      this.#changed();
      $('custom-params').lastElementChild?.querySelector('input')?.focus();
    });
    $('custom-add-row').addEventListener('click', () => {
      const n = parseNames($('custom-passenger').value).length;
      this.#addRow(Array.from({ length: n }, () => '0'));
      this.#renumber();
      this.#changed();
    });
    // New passenger names: every row gets one entry per name (kept where it was, 0 added).
    $('custom-passenger').addEventListener('change', () => this.#reshape());
  }

  /** Shows a custom system. */
  fill(sys) {
    $('custom-name').value = sys.name ?? '';
    $('custom-passenger').value = sys.passenger.join(', ');
    $('custom-driver').value = sys.driver ?? '';
    $('custom-params').replaceChildren();
    for (const [name, value] of Object.entries(sys.parameters)) this.#addParam(name, value);
    $('custom-U').value = sys.passenger_potential ?? '';
    $('custom-Vd').value = sys.driver_potential ?? '';
    $('custom-constraints').replaceChildren();
    for (const row of sys.constraints) this.#addRow(row);
    this.#renumber();
  }

  /** The custom system shown; fields that cannot be sent are pushed to `invalid`. */
  read(invalid) {
    const { system, invalid: found } = customFromFields({
      name: $('custom-name').value,
      passenger: $('custom-passenger').value,
      driver: $('custom-driver').value,
      parameters: [...$('custom-params').querySelectorAll('.custom-param')].map((row) => [
        row.querySelector('.param-name').value,
        row.querySelector('.param-value').value,
      ]),
      passenger_potential: $('custom-U').value,
      driver_potential: $('custom-Vd').value,
      constraints: [...$('custom-constraints').querySelectorAll('.custom-row')].map((row) =>
        [...row.querySelectorAll('.custom-cell input')].map((input) => input.value),
      ),
    });
    invalid.push(...found);
    return system;
  }

  #addParam(name, value) {
    const row = el('div', 'field custom-param');
    const nameInput = input('param-name', name, 'parameter name');
    const valueInput = input('param-value', Number.isNaN(value) ? '' : String(value), `value of ${name || 'the parameter'}`);
    valueInput.inputMode = 'decimal';
    const path = () => {
      const n = nameInput.value.trim();
      row.dataset.path = n ? `system.parameters.${n}` : 'system.parameters';
      valueInput.setAttribute('aria-label', `value of ${n || 'the parameter'}`);
    };
    nameInput.addEventListener('input', path);
    path();
    const remove = el('button', 'icon', '×');
    remove.type = 'button';
    remove.title = 'Remove this parameter';
    remove.setAttribute('aria-label', 'remove this parameter');
    remove.addEventListener('click', () => {
      row.remove();
      this.#buttons();
      this.#changed();
    });
    row.append(nameInput, el('span', 'eq', '='), valueInput, remove);
    $('custom-params').append(row);
    this.#buttons();
  }

  #addRow(entries) {
    const row = el('div', 'custom-row');
    for (const entry of entries) {
      const cell = el('label', 'custom-cell field');
      cell.append(el('span', 'cell-name'), input('formula', entry));
      row.append(cell);
    }
    const remove = el('button', 'icon', '×');
    remove.type = 'button';
    remove.title = 'Remove this constraint';
    remove.setAttribute('aria-label', 'remove this constraint');
    remove.addEventListener('click', () => {
      row.remove();
      this.#renumber();
      this.#changed();
    });
    row.append(remove);
    $('custom-constraints').append(row);
  }

  #reshape() {
    const names = parseNames($('custom-passenger').value);
    for (const row of $('custom-constraints').querySelectorAll('.custom-row')) {
      const cells = [...row.querySelectorAll('.custom-cell')];
      const values = cells.map((c) => c.querySelector('input').value);
      for (const c of cells) c.remove();
      const remove = row.lastElementChild;
      names.forEach((_, j) => {
        const cell = el('label', 'custom-cell field');
        cell.append(el('span', 'cell-name'), input('formula', values[j] ?? '0'));
        row.insertBefore(cell, remove);
      });
    }
    this.#renumber();
  }

  // Paths and labels follow the rows' order and the passenger names; a system keeps at least
  // one constraint, and at most one fewer than its passengers.
  #renumber() {
    const names = parseNames($('custom-passenger').value);
    const rows = [...$('custom-constraints').querySelectorAll('.custom-row')];
    rows.forEach((row, i) => {
      row.dataset.path = `system.constraints[${i}]`;
      row.querySelectorAll('.custom-cell').forEach((cell, j) => {
        const name = names[j] ?? `#${j + 1}`;
        cell.dataset.path = `system.constraints[${i}][${j}]`;
        cell.querySelector('.cell-name').textContent = name;
        cell.querySelector('input').setAttribute('aria-label', `constraint ${i + 1}, coefficient of the velocity of ${name}`);
      });
      row.querySelector('.icon').disabled = rows.length <= 1;
    });
    $('custom-add-row').disabled = rows.length >= Math.max(1, names.length - 1);
  }

  #buttons() {
    $('custom-add-param').disabled = $('custom-params').children.length >= this.maxParameters;
  }

  // Rows and parameters added or removed: the form and the URL follow, as for an edit.
  #changed() {
    $('custom-editor').dispatchEvent(new Event('change', { bubbles: true }));
  }
}

function input(className, value, label) {
  const i = el('input', className);
  i.type = 'text';
  i.spellcheck = false;
  i.autocomplete = 'off';
  i.value = value;
  if (label) i.setAttribute('aria-label', label);
  return i;
}
