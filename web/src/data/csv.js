// CSV as the page writes and reads it (RFC 4180): a field quoted where it holds a comma, a
// quote or a line break, and a reader of such text into rows of fields, for the downloads
// and for a sweep's CSV opened from a file. Pure, so node tests cover it.

/** A field as written: quoted (its quotes doubled) where it holds `,`, `"` or a line break. */
export function csvField(s) {
  const t = String(s);
  return /[",\n\r]/.test(t) ? `"${t.replace(/"/g, '""')}"` : t;
}

/**
 * The rows of CSV `text`, each a list of field strings: quoted fields may hold commas, quotes
 * (doubled) and line breaks; lines end in `\n` or `\r\n`; a byte-order mark and empty lines are
 * skipped. Throws an Error on a quoted field that is never closed.
 */
export function parseCSV(text) {
  const rows = [];
  let row = [];
  let field = '';
  let quoted = false;
  const end = () => {
    row.push(field);
    if (row.length > 1 || row[0] !== '') rows.push(row);
    row = [];
    field = '';
  };
  for (let i = text.charCodeAt(0) === 0xfeff ? 1 : 0; i < text.length; i++) {
    const c = text[i];
    if (quoted) {
      if (c !== '"') field += c;
      else if (text[i + 1] === '"') field += text[i++];
      else quoted = false;
    } else if (c === '"') quoted = true;
    else if (c === ',') {
      row.push(field);
      field = '';
    } else if (c === '\n') end();
    else if (c === '\r') {
      if (text[i + 1] === '\n') i++;
      end();
    } else field += c;
  }
  if (quoted) throw new Error('a quoted field is never closed');
  if (field !== '' || row.length) end();
  return rows;
}
