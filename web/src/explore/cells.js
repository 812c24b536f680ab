// Rows of formula entries labelled by coordinate names, as the custom-system editor shows the
// constraint matrix A and the mass matrix M: a `.custom-row` of `.custom-cell`s, each a small
// name over an input, whose `data-path` is the API's path of the entry
// (`system.constraints[0][1]`, `system.mass[2]`), so a server error lands under its row.

import { el, removeButton, textInput } from '../draw/dom.js';

/** A row of cells holding `entries`, with a × button when `onRemove` is given (`what`: what
 *  the row is, for its title). */
export function cellRow(entries, { what, onRemove } = {}) {
  const row = el('div', 'custom-row');
  row.append(...entries.map(cell));
  if (onRemove) {
    row.append(
      removeButton(`Remove this ${what}`, `remove this ${what}`, () => {
        row.remove();
        onRemove();
      }),
    );
  }
  return row;
}

/** The entries of a row, as typed. */
export function rowEntries(row) {
  return [...row.querySelectorAll('.custom-cell input')].map((input) => input.value);
}

/**
 * Gives `row` one cell per name, at paths `${path}[j]`: entries kept by position, `fill(j)`
 * for new ones; each cell labelled with its name and described by `describe(name)`.
 */
export function shapeRow(row, names, path, describe, fill) {
  let cells = [...row.querySelectorAll('.custom-cell')];
  if (cells.length !== names.length) {
    const values = rowEntries(row);
    for (const c of cells) c.remove();
    cells = names.map((_, j) => cell(values[j] ?? fill(j)));
    const remove = row.querySelector(':scope > .icon');
    for (const c of cells) row.insertBefore(c, remove);
  }
  cells.forEach((c, j) => {
    const name = names[j] || `#${j + 1}`;
    c.dataset.path = `${path}[${j}]`;
    c.querySelector('.cell-name').textContent = name;
    c.querySelector('input').setAttribute('aria-label', describe(name));
  });
}

function cell(value) {
  const c = el('label', 'custom-cell field');
  c.append(el('span', 'cell-name'), textInput('formula', String(value)));
  return c;
}
