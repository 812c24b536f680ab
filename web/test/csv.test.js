import assert from 'node:assert/strict';
import { test } from 'node:test';
import { csvField, parseCSV } from '../src/data/csv.js';

test('a field is quoted where it holds a comma, a quote or a line break', () => {
  assert.equal(csvField('plain'), 'plain');
  assert.equal(csvField(0.5), '0.5');
  assert.equal(csvField('a,b'), '"a,b"');
  assert.equal(csvField('say "hi"'), '"say ""hi"""');
  assert.equal(csvField('two\nlines'), '"two\nlines"');
  assert.equal(csvField('cr\r'), '"cr\r"');
});

test('CSV text reads back into its rows and fields', () => {
  const fields = ['plain', 'a,b', 'say "hi"', 'two\nlines', '', '{"x":[1,2]}'];
  assert.deepEqual(parseCSV(`${fields.map(csvField).join(',')}\n`), [fields]);
  assert.deepEqual(parseCSV('a,b\r\n1,\r\n\r\n,2'), [['a', 'b'], ['1', ''], ['', '2']], 'CRLF, empty fields, a blank line, no last line end');
  assert.deepEqual(parseCSV('\ufeffa\n'), [['a']], 'a byte-order mark');
  assert.deepEqual(parseCSV('"a""b",c\n""\n'), [['a"b', 'c']], 'a row of one empty field is a blank line');
  assert.deepEqual(parseCSV(''), []);
  assert.throws(() => parseCSV('a,"b\n'), /a quoted field is never closed/);
});
