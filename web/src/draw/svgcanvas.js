// A stand-in for a canvas 2D context that writes SVG, the page's one SVG writer: the subset of
// CanvasRenderingContext2D the heat map, the x–y plots and the charts' exports draw with
// (rectangles, text, paths with circles, a dash, a clip, a linear gradient, save/restore,
// translate/rotate, and text widths estimated from the font size). Drawing code written once
// for the canvas then also gives a vector file.
// Pure (no DOM), so node tests cover it. A device-pixel scale set with `setTransform` is
// ignored: the SVG is in CSS pixels.

const ANCHOR = { left: 'start', start: 'start', center: 'middle', right: 'end', end: 'end' };
// Canvas baselines are of the em box: its top and bottom edges, and its centre ('central').
const BASELINE = { top: 'text-before-edge', hanging: 'hanging', middle: 'central', alphabetic: 'auto', bottom: 'text-after-edge' };

/** Text for SVG markup: `&`, `<`, `>` and `"` escaped. */
export const esc = (t) => String(t).replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;').replace(/"/g, '&quot;');
const n = (v) => String(Math.round(v * 100) / 100);

// A canvas font (`600 11px system-ui, sans-serif`) as SVG attributes, which more SVG tools
// read than a CSS `font` shorthand.
function fontAttributes(font) {
  const m = /^\s*(?:(normal|bold|bolder|lighter|\d{3})\s+)?(\d+(?:\.\d+)?)px\s+(.+)$/.exec(font);
  if (!m) return `style="font: ${esc(font)}"`;
  return `${m[1] ? `font-weight="${m[1]}" ` : ''}font-size="${m[2]}" font-family="${esc(m[3])}"`;
}

// A rectangle with a positive width and height, as SVG requires (a canvas takes either sign).
function box(x, y, w, h) {
  return `x="${n(Math.min(x, x + w))}" y="${n(Math.min(y, y + h))}" width="${n(Math.abs(w))}" height="${n(Math.abs(h))}"`;
}

export class SvgContext {
  constructor(width, height) {
    this.width = width;
    this.height = height;
    this.parts = [];
    this.defs = [];
    this.ids = 0;
    this.path = '';
    this.stack = [];
    this.state = {
      fillStyle: '#000',
      strokeStyle: '#000',
      lineWidth: 1,
      font: '10px sans-serif',
      textAlign: 'start',
      textBaseline: 'alphabetic',
      transform: [],
      clip: null,
      dash: [],
    };
  }

  setTransform() {}
  clearRect() {}

  save() {
    this.stack.push({ ...this.state, transform: [...this.state.transform], dash: [...this.state.dash] });
  }

  restore() {
    if (this.stack.length) this.state = this.stack.pop();
  }

  translate(x, y) {
    this.state.transform.push(`translate(${n(x)} ${n(y)})`);
  }

  rotate(radians) {
    this.state.transform.push(`rotate(${n((radians * 180) / Math.PI)})`);
  }

  createLinearGradient(x0, y0, x1, y1) {
    const id = `g${++this.ids}`;
    const stops = [];
    this.defs.push(() => `<linearGradient id="${id}" gradientUnits="userSpaceOnUse" x1="${n(x0)}" y1="${n(y0)}" x2="${n(x1)}" y2="${n(y1)}">${stops.map(([o, c]) => `<stop offset="${o}" stop-color="${esc(c)}"/>`).join('')}</linearGradient>`);
    return { url: `url(#${id})`, addColorStop: (offset, colour) => stops.push([offset, colour]) };
  }

  beginPath() {
    this.path = '';
  }

  moveTo(x, y) {
    this.path += `M${n(x)} ${n(y)}`;
  }

  lineTo(x, y) {
    this.path += `L${n(x)} ${n(y)}`;
  }

  /** A whole circle (the markers' only arc). */
  arc(x, y, r) {
    this.path += `M${n(x + r)} ${n(y)}A${n(r)} ${n(r)} 0 1 0 ${n(x - r)} ${n(y)}A${n(r)} ${n(r)} 0 1 0 ${n(x + r)} ${n(y)}`;
  }

  closePath() {
    this.path += 'Z';
  }

  setLineDash(dash) {
    this.state.dash = [...(dash ?? [])];
  }

  rect(x, y, w, h) {
    this.path += `M${n(x)} ${n(y)}h${n(w)}v${n(h)}h${n(-w)}Z`;
  }

  clip() {
    const id = `c${++this.ids}`;
    // The clipped elements sit in an untransformed group, so the clip carries the transform.
    const d = this.path;
    const t = this.state.transform.length ? ` transform="${this.state.transform.join(' ')}"` : '';
    this.defs.push(() => `<clipPath id="${id}"><path d="${d}"${t}/></clipPath>`);
    this.state.clip = id;
  }

  stroke() {
    if (!this.path) return;
    const dash = this.state.dash.length ? ` stroke-dasharray="${this.state.dash.map(n).join(' ')}"` : '';
    this.#emit(`<path d="${this.path}" fill="none" stroke="${this.#paint(this.state.strokeStyle)}" stroke-width="${n(this.state.lineWidth)}"${dash}`);
  }

  fill() {
    if (!this.path) return;
    this.#emit(`<path d="${this.path}" fill="${this.#paint(this.state.fillStyle)}"`);
  }

  fillRect(x, y, w, h) {
    this.#emit(`<rect ${box(x, y, w, h)} fill="${this.#paint(this.state.fillStyle)}"`);
  }

  strokeRect(x, y, w, h) {
    this.#emit(`<rect ${box(x, y, w, h)} fill="none" stroke="${this.#paint(this.state.strokeStyle)}" stroke-width="${n(this.state.lineWidth)}"`);
  }

  /** The width of `text` in the current font, estimated (SVG has no layout here): an average
   *  glyph of 0.56 em, enough to wrap captions and lay out legends. */
  measureText(text) {
    const size = Number(/(\d+(?:\.\d+)?)px/.exec(this.state.font)?.[1] ?? 10);
    return { width: 0.56 * size * String(text).length };
  }

  fillText(text, x, y) {
    const s = this.state;
    const attrs = `x="${n(x)}" y="${n(y)}" text-anchor="${ANCHOR[s.textAlign] ?? 'start'}" dominant-baseline="${BASELINE[s.textBaseline] ?? 'auto'}" ${fontAttributes(s.font)} fill="${this.#paint(s.fillStyle)}"`;
    this.#emit(`<text ${attrs}`, `>${esc(text)}</text>`);
  }

  /** What was drawn, its definitions first, to place inside an `<svg>` or a `<g>`. */
  content() {
    const defs = this.defs.length ? `<defs>${this.defs.map((d) => d()).join('')}</defs>` : '';
    return `${defs}${this.parts.join('')}`;
  }

  /** The SVG document. */
  toString() {
    return `<svg xmlns="http://www.w3.org/2000/svg" width="${n(this.width)}" height="${n(this.height)}" viewBox="0 0 ${n(this.width)} ${n(this.height)}">${this.content()}</svg>\n`;
  }

  #paint(style) {
    return typeof style === 'object' && style?.url ? style.url : esc(style);
  }

  // An element with the current transform and clip; `close` ends it (`/>` by default).
  #emit(open, close = '/>') {
    const { transform, clip } = this.state;
    const t = transform.length ? ` transform="${transform.join(' ')}"` : '';
    const element = `${open}${t}${close}`;
    this.parts.push(clip ? `<g clip-path="url(#${clip})">${element}</g>` : element);
  }
}

// The drawing state, read and written as a canvas context's properties (save and restore
// keep it whole).
for (const name of ['fillStyle', 'strokeStyle', 'lineWidth', 'font', 'textAlign', 'textBaseline']) {
  Object.defineProperty(SvgContext.prototype, name, {
    get() {
      return this.state[name];
    },
    set(value) {
      this.state[name] = value;
    },
  });
}
