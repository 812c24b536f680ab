// Small DOM helpers every view uses: an element with a class and text, a select's option, a
// text input for names and formulas, a × button that removes something, a download of text
// made in the page, and a banner shown when needed.

/** `<tag class=className>text</tag>`; class and text only when given. */
export function el(tag, className, text) {
  const e = document.createElement(tag);
  if (className) e.className = className;
  if (text !== undefined) e.textContent = text;
  return e;
}

/** `<option value=value>text</option>`. */
export function option(value, text) {
  const o = document.createElement('option');
  o.value = value;
  o.textContent = text;
  return o;
}

/** `<input type=text class=className>` with `value`, no spell check or autocomplete, and an
 *  accessible `label` when given. */
export function textInput(className, value, label) {
  const i = el('input', className);
  i.type = 'text';
  i.spellcheck = false;
  i.autocomplete = 'off';
  i.value = value;
  if (label) i.setAttribute('aria-label', label);
  return i;
}

/** A × button titled `title`, read out as `label`, calling `onClick`. */
export function removeButton(title, label, onClick) {
  const b = el('button', 'icon', '×');
  b.type = 'button';
  b.title = title;
  b.setAttribute('aria-label', label);
  b.addEventListener('click', onClick);
  return b;
}

/** Saves `text` as the file `name` of MIME type `type`. */
export function download(name, type, text) {
  const url = URL.createObjectURL(new Blob([text], { type }));
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

/** Shows `text` in a banner that is hidden until needed. */
export function banner(node, text) {
  node.textContent = text;
  node.hidden = false;
}
