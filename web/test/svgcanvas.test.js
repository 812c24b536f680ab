import assert from 'node:assert/strict';
import { test } from 'node:test';
import { SvgContext } from '../src/draw/svgcanvas.js';

test('canvas drawing calls become SVG elements, in order', () => {
  const ctx = new SvgContext(200, 100);
  ctx.setTransform(2, 0, 0, 2, 0, 0); // a device-pixel scale: ignored
  ctx.fillStyle = '#15803d';
  ctx.fillRect(10, 20, 30, 40);
  ctx.font = '600 11px system-ui, sans-serif';
  ctx.textAlign = 'center';
  ctx.textBaseline = 'middle';
  ctx.fillStyle = '#fff';
  ctx.fillText('B <&>', 25, 40);
  const svg = ctx.toString();
  assert.match(svg, /^<svg xmlns="http:\/\/www.w3.org\/2000\/svg" width="200" height="100" viewBox="0 0 200 100">/);
  assert.match(svg, /<rect x="10" y="20" width="30" height="40" fill="#15803d"\/>/);
  assert.match(svg, /<text x="25" y="40" text-anchor="middle" dominant-baseline="central" font-weight="600" font-size="11" font-family="system-ui, sans-serif" fill="#fff">B &lt;&amp;&gt;<\/text>/);
  assert.ok(svg.indexOf('<rect') < svg.indexOf('<text'), 'drawn in order');
  ctx.fillRect(10, 10, -4, -2);
  assert.match(ctx.toString(), /<rect x="6" y="8" width="4" height="2"/, 'a negative size is flipped');
});

test('save and restore keep transforms apart; a clip carries the transform of its time', () => {
  const ctx = new SvgContext(100, 100);
  ctx.save();
  ctx.translate(12, 30);
  ctx.rotate(-Math.PI / 2);
  ctx.fillText('y', 0, 0);
  ctx.restore();
  ctx.fillText('x', 5, 5);
  ctx.save();
  ctx.translate(0, 10);
  ctx.beginPath();
  ctx.rect(0, 0, 10, 10);
  ctx.clip();
  ctx.moveTo(0, 10);
  ctx.lineTo(10, 0);
  ctx.stroke();
  ctx.restore();
  ctx.fillRect(0, 0, 1, 1);
  const svg = ctx.toString();
  assert.match(svg, /<text[^>]*transform="translate\(12 30\) rotate\(-90\)"[^>]*>y<\/text>/);
  assert.match(svg, /<text x="5" y="5"[^>]*>x<\/text>/);
  assert.doesNotMatch(svg.match(/<text x="5"[^>]*>/)[0], /transform/);
  assert.match(svg, /<clipPath id="c1"><path d="M0 0h10v10h-10Z" transform="translate\(0 10\)"\/><\/clipPath>/);
  assert.match(svg, /<g clip-path="url\(#c1\)"><path d="M0 0h10v10h-10ZM0 10L10 0" fill="none"[^>]*transform="translate\(0 10\)"\/><\/g>/);
  assert.match(svg, /<\/g><rect x="0" y="0" width="1" height="1"[^>]*\/><\/svg>/, 'the clip ends with restore');
});

test('a linear gradient is a definition the fill refers to', () => {
  const ctx = new SvgContext(50, 50);
  const grad = ctx.createLinearGradient(0, 40, 0, 0);
  grad.addColorStop(0, '#440154');
  grad.addColorStop(1, '#fde725');
  ctx.fillStyle = grad;
  ctx.fillRect(0, 0, 10, 40);
  const svg = ctx.toString();
  assert.match(svg, /<defs><linearGradient id="g1" gradientUnits="userSpaceOnUse" x1="0" y1="40" x2="0" y2="0"><stop offset="0" stop-color="#440154"\/><stop offset="1" stop-color="#fde725"\/><\/linearGradient><\/defs>/);
  assert.match(svg, /<rect x="0" y="0" width="10" height="40" fill="url\(#g1\)"\/>/);
});
