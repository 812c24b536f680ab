// Words the page shows for things the API names by id: a method's label with its TeX-like
// exponent (`X^{0,1}`, `X^0.5`) written with superscripts, a request field's path
// (`levels`, `params.epsilon`, `methods[1].alpha`) as the label the user sees beside that
// field. Pure functions, so node tests cover them.

const SUPER = {
  0: '⁰', 1: '¹', 2: '²', 3: '³', 4: '⁴', 5: '⁵', 6: '⁶', 7: '⁷', 8: '⁸', 9: '⁹',
  '-': '⁻', '+': '⁺', '=': '⁼', '(': '⁽', ')': '⁾', '.': '·', ',': '˒', 'α': 'ᵅ', 'β': 'ᵝ', n: 'ⁿ', i: 'ⁱ',
};

/** `text` in superscript characters (`-12` → `⁻¹²`); null when one has none. */
export function superscript(text) {
  const chars = [...String(text)];
  return chars.every((c) => SUPER[c]) ? chars.map((c) => SUPER[c]).join('') : null;
}

/** The label of `label`'s method when a sweep's axis sets its parameter (`paths`, the axes'):
 *  its exponent dropped and the swept parameter named, `X^0.5` → `X (α swept)`, since
 *  each cell runs it with another value; else the label for people. `index` is the method's
 *  place in the sweep's list. */
export function sweptLabel(label, paths, index) {
  const swept = paths
    .map((p) => /^methods(?:\[(\d+)\])?\.(\w+)$/.exec(p))
    .filter((m) => m && (m[1] === undefined || Number(m[1]) === index))
    .map((m) => symbol(m[2]));
  if (!swept.length) return humanLabel(label);
  return `${String(label ?? '').replace(/\^.*$/, '')} (${swept.join(', ')} swept)`;
}

/** A method label for people: `A^{0,1}` → `A⁰˒¹`, `A^0.4` → `A⁰·⁴`; an exponent
 *  with a character that has no superscript keeps a plain `^(…)`. */
export function humanLabel(label) {
  return String(label ?? '').replace(/\^(?:\{([^}]*)\}|([0-9.,+\-=()αβni]+))/g, (whole, braced, bare) => {
    const text = braced ?? bare;
    const sup = text ? superscript(text) : null;
    if (sup !== null) return sup;
    return braced === undefined ? whole : `^(${text})`;
  });
}

/** The labels of the Explore form's fields and the Work–precision settings, by API path. */
const FIELDS = {
  system: 'System',
  preset: 'Preset',
  params: 'Parameters',
  q: 'q(0)',
  v: 'q̇(0)',
  step: 'Step h',
  t_end: 'Final time',
  points: 'Points per curve',
  methods: 'Methods',
  integrals: 'Integrals',
  window: 'Running-mean window',
  levels: 'Step sizes',
  steps: 'Steps h',
  repeats: 'Repeats',
};

const GREEK = 'alpha beta gamma delta epsilon zeta eta theta iota kappa lambda mu nu xi omicron pi rho sigma tau upsilon phi chi psi omega'.split(' ');

/** A name of a Greek letter as the letter (`epsilon` → `ε`); any other name as it is. */
export function symbol(name) {
  const i = GREEK.indexOf(name);
  return i < 0 ? name : String.fromCodePoint(0x3b1 + i + (i >= 17 ? 1 : 0));
}

/**
 * The label the page shows for an API field path: `levels` → "Step sizes",
 * `params.epsilon` → "ε (epsilon)", `methods[1].alpha` → "method 2, α", `methods.alpha` → "α
 * (every method)", `q[2]` → "q(0),
 * entry 3", `system.constraints[0][1]` → "System (constraints…)"; null for no path.
 */
export function fieldLabel(path) {
  if (!path) return null;
  const m = /^([a-z_]+)(.*)$/i.exec(path);
  if (!m) return path;
  const [, head, rest] = m;
  if (head === 'params' && rest.startsWith('.')) {
    const name = rest.slice(1);
    const s = symbol(name);
    return s === name ? name : `${s} (${name})`;
  }
  if (head === 'methods') {
    // A sweep's axis over every listed method's parameter.
    if (/^\.\w+$/.test(rest)) return `${symbol(rest.slice(1))} (every method)`;
    const item = /^\[(\d+)\](?:\.(\w+))?/.exec(rest);
    if (item) return `method ${Number(item[1]) + 1}${item[2] ? `, ${item[2] === 'composition' ? 'composition' : symbol(item[2])}` : ''}`;
  }
  const base = FIELDS[head] ?? head;
  const index = /^\[(\d+)\]$/.exec(rest);
  if (index) return `${base}, entry ${Number(index[1]) + 1}`;
  if (head === 'system' && rest) return `${base} (${rest.replace(/^\./, '')})`;
  return rest ? `${base} ${rest}` : base;
}
