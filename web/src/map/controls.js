// The Map view's own controls: one or two axes (what each sets, how its values are spaced,
// the numbers, and a preview of the values it stands for), the method and integral shown and
// the colouring. Filled from settings and read back into them; an error whose `path` names
// an axis field (`axes[1].path`, `axes[0].linspace[2]`, `axes`) is shown under that field.

import { KINDS, MAX_AXES, cellCount, checkAxis, expandAxis } from './sweep.js';
import { fmt } from './sweepresult.js';
import { parseList } from '../data/state.js';
import { el, option, removeButton, textInput } from '../draw/dom.js';

const KIND_TEXT = {
  linspace: ['evenly spaced', 'start, stop, count'],
  logspace: ['log-spaced', 'start, stop, count (start, stop > 0)'],
  values: ['listed values', 'values, comma-separated'],
};

export class MapControls {
  /** `onChange()`: any control changed (the view rewrites its URL, redraws). */
  constructor(root, { onChange }) {
    this.root = root;
    this.onChange = onChange;
    this.axesBox = root.querySelector('.map-axes');
    this.addAxis = root.querySelector('.map-add-axis');
    this.count = root.querySelector('.map-count');
    this.paths = root.querySelector('#map-paths');
    this.method = root.querySelector('#map-method');
    this.integral = root.querySelector('#map-integral');
    this.color = root.querySelector('#map-color');
    this.methodCount = 1;
    this.addAxis.addEventListener('click', () => {
      const axes = this.readAxes();
      axes.unshift({ path: '', kind: 'linspace', numbers: [] });
      this.#axes(axes.slice(0, MAX_AXES));
      this.changed();
    });
    root.addEventListener('change', () => this.changed());
    root.addEventListener('input', (e) => {
      if (e.target.closest('.map-axis')) this.#previews();
    });
  }

  changed() {
    this.#previews();
    this.onChange();
  }

  /** Shows settings: the axes, and the choices of method and integral (`methods`: labels). */
  fill(settings) {
    this.#axes(settings.axes);
    this.color.value = settings.color;
    this.wanted = { method: settings.method, integral: settings.integral };
  }

  /** The methods and integrals offered (labels; ids), keeping the choice where it still is. */
  offer(methods, integrals) {
    const method = this.wanted?.method ?? Number(this.method.value || 0);
    const integral = this.wanted?.integral || this.integral.value;
    this.method.replaceChildren(...methods.map((label, i) => option(String(i), label)));
    this.method.value = String(method < methods.length ? method : 0);
    this.integral.replaceChildren(...integrals.map((id) => option(id, id)));
    this.integral.value = integrals.includes(integral) ? integral : integrals.includes('energy') ? 'energy' : integrals[0] ?? '';
    this.methodCount = Math.max(1, methods.length);
    this.wanted = null;
    this.#previews();
  }

  /** The paths the axis inputs suggest. */
  suggest(paths) {
    this.paths.replaceChildren(...paths.map((p) => option(p, '')));
  }

  /** The settings shown (without `run`). */
  read() {
    return {
      axes: this.readAxes(),
      method: this.wanted?.method ?? Number(this.method.value || 0),
      integral: this.wanted?.integral ?? this.integral.value,
      color: this.color.value,
      run: false,
    };
  }

  readAxes() {
    return [...this.axesBox.querySelectorAll('.map-axis')].map((row) => ({
      path: row.querySelector('.axis-path').value,
      kind: row.querySelector('.axis-kind').value,
      numbers: parseList(row.querySelector('.axis-numbers').value),
    }));
  }

  /** Marks the axes' mistakes before a request; returns whether there were any. */
  check() {
    this.clearErrors();
    const errors = this.readAxes().flatMap((a, i) => checkAxis(a, i));
    for (const e of errors) this.showError(e.path, e.message);
    return errors.length > 0;
  }

  /** Shows `message` at the field `path` names; false when no control of the view has it. */
  showError(path, message) {
    let p = path ?? '';
    while (p) {
      const target = this.root.querySelector(`[data-path="${CSS.escape(p)}"]`);
      if (target) {
        target.classList.add('invalid');
        const note = el('p', 'field-error', message);
        note.setAttribute('role', 'alert');
        target.append(note);
        target.scrollIntoView?.({ block: 'nearest' });
        return true;
      }
      const cut = Math.max(p.lastIndexOf('.'), p.lastIndexOf('['));
      if (cut <= 0) break;
      p = p.slice(0, cut);
    }
    return false;
  }

  clearErrors() {
    for (const e of this.root.querySelectorAll('.field-error')) e.remove();
    for (const e of this.root.querySelectorAll('.invalid')) e.classList.remove('invalid');
  }

  // One row per axis, the first on top; the rows are named by where they are drawn.
  #axes(axes) {
    const rows = axes.map((a, i) => {
      const row = el('div', 'map-axis');
      row.dataset.path = `axes[${i}]`;
      const head = el('div', 'map-axis-head');
      const where = axes.length === 1 ? 'Axis (along x)' : i === 0 ? 'First axis (rows, y)' : 'Last axis (columns, x)';
      head.append(el('span', 'label', where));
      if (axes.length > 1) {
        head.append(
          removeButton('Remove this axis', `remove axis ${i + 1}`, () => {
            const now = this.readAxes();
            now.splice(i, 1);
            this.#axes(now);
            this.changed();
          }),
        );
      }
      const pathField = el('div', 'field');
      pathField.dataset.path = `axes[${i}].path`;
      const pathInput = textInput('axis-path', a.path, `Axis ${i + 1}: what it sets`);
      pathInput.setAttribute('list', 'map-paths');
      pathInput.placeholder = 'params.<name>, step, q[0], methods.<name>…';
      pathField.append(labelFor(pathInput, 'Sets'), pathInput);
      const kind = el('select', 'axis-kind');
      kind.setAttribute('aria-label', `Axis ${i + 1}: spacing`);
      kind.append(...KINDS.map((k) => option(k, KIND_TEXT[k][0])));
      kind.value = a.kind;
      const numbersField = el('div', 'field');
      numbersField.dataset.path = `axes[${i}].${a.kind}`;
      const numbers = textInput('axis-numbers', a.numbers.map(String).join(', '), `Axis ${i + 1}: ${KIND_TEXT[a.kind][1]}`);
      numbers.inputMode = 'decimal';
      numbersField.append(labelFor(numbers, KIND_TEXT[a.kind][1]), numbers);
      kind.addEventListener('change', () => {
        numbersField.dataset.path = `axes[${i}].${kind.value}`;
        numbersField.querySelector('label').textContent = KIND_TEXT[kind.value][1];
      });
      const kindField = el('div', 'field');
      kindField.append(labelFor(kind, 'Spacing'), kind);
      const line = el('div', 'row map-axis-values');
      line.append(kindField, numbersField);
      row.append(head, pathField, line, el('p', 'hint axis-preview'));
      return row;
    });
    this.axesBox.replaceChildren(...rows);
    this.addAxis.hidden = axes.length >= MAX_AXES;
    this.#previews();
  }

  // Under each axis the values it stands for; under the axes the number of cells and runs.
  #previews() {
    const axes = this.readAxes();
    [...this.axesBox.querySelectorAll('.map-axis')].forEach((row, i) => {
      const values = expandAxis(axes[i]);
      row.querySelector('.axis-preview').textContent = values ? preview(values) : 'Not a valid axis yet.';
    });
    const cells = cellCount(axes);
    const runs = cells === null ? null : cells * this.methodCount;
    this.count.textContent = cells === null ? '' : `${cells} cells × ${this.methodCount} method${this.methodCount === 1 ? '' : 's'} = ${runs} runs.`;
  }
}

/** "21 values: 0.3, 0.32, 0.34, …, 0.7". */
export function preview(values) {
  const shown = values.length <= 6 ? values.map(fmt) : [...values.slice(0, 3).map(fmt), '…', fmt(values[values.length - 1])];
  return `${values.length} value${values.length === 1 ? '' : 's'}: ${shown.join(', ')}`;
}

let ids = 0;
function labelFor(control, text) {
  control.id ||= `map-control-${++ids}`;
  const l = el('label', '', text);
  l.htmlFor = control.id;
  return l;
}
