// One Tab stop for a table of focusable cells, arrow keys inside (as a grid widget does): the
// cell last focused keeps tabindex 0, every other focusable cell -1; ←/→ move along the row,
// ↑/↓ to the nearest focusable cell of the same column in the row above or below, Home/End
// to the row's ends. Enter or Space activates the cell (its click). `cells` selects the
// focusable cells.

/** Makes `table`'s `cells` (a selector) one Tab stop with arrow keys. */
export function gridKeys(table, cells) {
  const all = () => [...table.querySelectorAll(cells)];
  const list = all();
  if (!list.length) return;
  for (const c of list) c.tabIndex = -1;
  list[0].tabIndex = 0;
  table.addEventListener('focusin', (e) => {
    const cell = e.target.closest?.(cells);
    if (!cell) return;
    for (const c of all()) c.tabIndex = c === cell ? 0 : -1;
  });
  table.addEventListener('keydown', (e) => {
    const cell = e.target.closest?.(cells);
    if (!cell) return;
    if (e.key === 'Enter' || e.key === ' ') {
      e.preventDefault();
      cell.click();
      return;
    }
    const next = target(cell, e.key, cells);
    if (next === undefined) return;
    e.preventDefault();
    next?.focus();
  });
}

/** The cell an arrow key moves to from `cell` (null: none there; undefined: not a move key). */
export function target(cell, key, cells) {
  const row = cell.parentElement;
  const inRow = (r) => [...r.children].filter((c) => c.matches(cells));
  const mine = inRow(row);
  const i = mine.indexOf(cell);
  switch (key) {
    case 'ArrowLeft':
      return mine[i - 1] ?? null;
    case 'ArrowRight':
      return mine[i + 1] ?? null;
    case 'Home':
      return mine[0] ?? null;
    case 'End':
      return mine[mine.length - 1] ?? null;
    case 'ArrowUp':
    case 'ArrowDown': {
      const rows = [...row.parentElement.children];
      const step = key === 'ArrowUp' ? -1 : 1;
      for (let r = rows.indexOf(row) + step; r >= 0 && r < rows.length; r += step) {
        const there = [...rows[r].children];
        const same = there[cell.cellIndex];
        if (same?.matches(cells)) return same;
        const near = inRow(rows[r]);
        if (near.length) return near.reduce((a, b) => (Math.abs(b.cellIndex - cell.cellIndex) < Math.abs(a.cellIndex - cell.cellIndex) ? b : a));
      }
      return null;
    }
    default:
      return undefined;
  }
}
