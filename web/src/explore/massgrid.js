// The mass matrix M in the custom-system editor's general form: the identity (no entries), a
// diagonal (one row of entries, at `system.mass[j]`) or a full symmetric matrix (a row per
// coordinate, at `system.mass[i][j]`), of numbers or formulas in the parameters. It follows
// the coordinates' names and keeps what it can when its shape or mode changes.

import { cellRow, rowEntries, shapeRow } from './cells.js';
import { massMode } from '../data/custom.js';

const $ = (id) => document.getElementById(id);

export class MassGrid {
  constructor() {
    this.names = [];
    this.mode = 'identity';
    $('custom-mass-mode').addEventListener('change', () => this.#remode($('custom-mass-mode').value));
  }

  /** Shows M (absent, a list or rows, as the API writes it) for the coordinates `names`. */
  fill(mass, names) {
    this.names = names;
    this.mode = massMode(mass);
    $('custom-mass-mode').value = this.mode;
    const rows = { identity: [], diagonal: [mass], full: mass }[this.mode];
    $('custom-mass').replaceChildren(...rows.map((r) => cellRow(r.map(String))));
    this.#shape();
  }

  /** The mode and entries shown, as `customFromFields` takes them. */
  read() {
    return { mode: this.mode, rows: [...$('custom-mass').children].map(rowEntries) };
  }

  /** New coordinate names: entries kept by position, 1 on the diagonal and 0 off it where new. */
  rename(names) {
    this.names = names;
    this.#shape();
  }

  // Another mode: a diagonal from the matrix's, a matrix from the diagonal (0 off it).
  #remode(mode) {
    const { rows } = this.read();
    const diagonal = this.names.map((_, i) => (this.mode === 'full' ? rows[i]?.[i] : this.mode === 'diagonal' ? rows[0]?.[i] : undefined) ?? '1');
    this.mode = mode;
    const next = { identity: [], diagonal: [diagonal], full: this.names.map((_, i) => this.names.map((__, j) => (i === j ? diagonal[i] : '0'))) }[mode];
    $('custom-mass').replaceChildren(...next.map((r) => cellRow(r)));
    this.#shape();
  }

  // One row (diagonal) or a row per coordinate (full), each with an entry per coordinate.
  #shape() {
    const box = $('custom-mass');
    const n = this.mode === 'full' ? this.names.length : this.mode === 'diagonal' ? 1 : 0;
    while (box.children.length > n) box.lastElementChild.remove();
    while (box.children.length < n) box.append(cellRow([]));
    [...box.children].forEach((row, i) => {
      if (this.mode === 'diagonal') {
        shapeRow(row, this.names, 'system.mass', (name) => `mass of ${name}`, () => '1');
      } else {
        const who = this.names[i] || `#${i + 1}`;
        row.dataset.path = `system.mass[${i}]`;
        shapeRow(row, this.names, `system.mass[${i}]`, (name) => `M entry (${who}, ${name})`, (j) => (i === j ? '1' : '0'));
      }
    });
  }
}
