// The custom-system editor's inputs (editor.js) read into the object `"system"` takes in a
// request (custom.js), in either form, with what cannot be sent said at its field. Pure
// functions, so node tests cover them.

/**
 * The custom system the editor's inputs describe and the inputs that cannot be sent as
 * `invalid` ({path, message}): a parameter without a name, given twice or whose value is not
 * a number; an invariant without a name or given twice. Formulas go as typed: the server
 * checks them and says where. `fields`: the texts of the inputs, the parameters and
 * invariants as [name, text] pairs, the constraints as rows of entries; in the general form
 * (`fields.coordinates` given) the mass as `{mode: identity | diagonal | full, rows}`.
 */
export function customFromFields(fields) {
  const invalid = [];
  const parameters = named(fields.parameters, 'system.parameters', 'parameter', invalid, (text) => {
    const value = String(text).trim() === '' ? NaN : Number(text);
    return Number.isFinite(value) ? { value } : { value, problem: 'needs a number' };
  });
  const constraints = fields.constraints.map((row) => [...row]);
  if (fields.coordinates === undefined) {
    const system = {
      name: fields.name,
      passenger: parseNames(fields.passenger),
      driver: fields.driver.trim(),
      parameters,
      passenger_potential: fields.passenger_potential,
      driver_potential: fields.driver_potential,
      constraints,
    };
    return { system, invalid };
  }
  const invariants = named(fields.invariants ?? [], 'system.invariants', 'invariant', invalid, (text) => ({ value: text }));
  const mass = massOf(fields.mass);
  const system = {
    name: fields.name,
    coordinates: parseNames(fields.coordinates),
    parameters,
    ...(mass ? { mass } : {}),
    potential: fields.potential,
    constraints,
    ...(Object.keys(invariants).length ? { invariants } : {}),
    detect_class: fields.detect_class !== false,
  };
  return { system, invalid };
}

// Named values from [name, text] pairs: each name once, trimmed; `read(text)` gives the value
// and what is wrong with it, if anything.
function named(pairs, path, what, invalid, read) {
  const out = {};
  for (const [rawName, text] of pairs) {
    const name = rawName.trim();
    if (!name) {
      invalid.push({ path, message: `${/^[aeiou]/.test(what) ? 'an' : 'a'} ${what} needs a name` });
      continue;
    }
    const { value, problem } = read(text);
    if (Object.hasOwn(out, name)) invalid.push({ path: `${path}.${name}`, message: `${what} '${name}' is given twice` });
    else if (problem) invalid.push({ path: `${path}.${name}`, message: `${what} '${name}' ${problem}` });
    out[name] = value;
  }
  return out;
}

/** M as the API takes it from the editor's mode and entries: none for the identity, a
 *  diagonal list, or the rows of a full matrix. */
function massOf(mass) {
  if (!mass || mass.mode === 'identity') return undefined;
  if (mass.mode === 'diagonal') return (mass.rows[0] ?? []).map(massEntry);
  return mass.rows.map((row) => row.map(massEntry));
}

/** A mass entry as typed: a number where it reads as one, else a formula. */
export function massEntry(text) {
  const t = String(text).trim();
  return t !== '' && Number.isFinite(Number(t)) ? Number(t) : t;
}

/** Comma-separated names as a list (blank items kept, for the server to name). */
export function parseNames(text) {
  const t = String(text).trim();
  return t === '' ? [] : t.split(',').map((s) => s.trim());
}
