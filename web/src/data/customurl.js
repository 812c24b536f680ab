// A custom system (custom.js) as query pairs, so a link brings it back. Both forms start with
// `custom=<name>` and list their parameters as `param.<name>=<value>` and each constraint row
// as `A=<entries>`; the paper's form adds `passenger=x1,x2`, `driver=zeta`, `U=…` and `Vd=…`,
// the general form `coordinates=x,y,theta`, `M=<diagonal>` or one `Mrow=<entries>` per row of
// a full mass matrix, `V=…`, `inv.<name>=<formula>` per invariant and `detect=0` when nhlab is
// not to look for the paper's class. Items are comma-separated; commas and `%` inside an item
// are written %2C and %25.

import { isGeneral, massMode } from './custom.js';
import { massEntry } from './customfields.js';

/** The query pairs of a custom system. */
export function encodeCustom(sys) {
  const out = [['custom', sys.name]];
  const general = isGeneral(sys);
  if (general) out.push(['coordinates', joinItems(sys.coordinates)]);
  else out.push(['passenger', joinItems(sys.passenger)], ['driver', sys.driver]);
  for (const [name, value] of Object.entries(sys.parameters)) out.push([`param.${name}`, String(value)]);
  if (!general) {
    out.push(['U', sys.passenger_potential], ['Vd', sys.driver_potential]);
    for (const row of sys.constraints) out.push(['A', joinItems(row)]);
    return out;
  }
  const mode = massMode(sys.mass);
  if (mode === 'diagonal') out.push(['M', joinItems(sys.mass)]);
  if (mode === 'full') for (const row of sys.mass) out.push(['Mrow', joinItems(row)]);
  out.push(['V', sys.potential]);
  for (const row of sys.constraints) out.push(['A', joinItems(row)]);
  for (const [name, formula] of Object.entries(sys.invariants ?? {})) out.push([`inv.${name}`, formula]);
  if (sys.detect_class === false) out.push(['detect', '0']);
  return out;
}

/** The custom system of a query (URLSearchParams), or null when it names none. Parameter
 *  values that do not parse are kept as NaN for the form to mark. */
export function decodeCustom(p) {
  if (!p.has('custom')) return null;
  const parameters = {};
  const invariants = {};
  for (const [key, value] of p) {
    if (key.startsWith('param.')) parameters[key.slice(6)] = Number(value);
    if (key.startsWith('inv.')) invariants[key.slice(4)] = value;
  }
  const constraints = p.getAll('A').map(splitItems);
  if (!p.has('coordinates')) {
    return {
      name: p.get('custom'),
      passenger: splitItems(p.get('passenger') ?? ''),
      driver: p.get('driver') ?? '',
      parameters,
      passenger_potential: p.get('U') ?? '',
      driver_potential: p.get('Vd') ?? '',
      constraints,
    };
  }
  const rows = p.getAll('Mrow').map((row) => splitItems(row).map(massEntry));
  const mass = p.has('M') ? splitItems(p.get('M')).map(massEntry) : rows.length ? rows : null;
  return {
    name: p.get('custom'),
    coordinates: splitItems(p.get('coordinates')),
    parameters,
    ...(mass ? { mass } : {}),
    potential: p.get('V') ?? '',
    constraints,
    ...(Object.keys(invariants).length ? { invariants } : {}),
    detect_class: p.get('detect') !== '0',
  };
}

function joinItems(items) {
  return items.map((s) => String(s).replace(/[%,]/g, (c) => (c === '%' ? '%25' : '%2C'))).join(',');
}

function splitItems(text) {
  if (text === '') return [];
  return text.split(',').map((s) => s.replace(/%(25|2C)/gi, (m) => (m === '%25' ? '%' : ',')));
}
