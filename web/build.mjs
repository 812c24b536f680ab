// Builds the page into dist/ (what the nhlab binary embeds): esbuild bundles src/main.js with
// uPlot and eventsource-parser into app-<hash>.js, their CSS into app-<hash>.css (named by
// their content, so a browser may keep them for good); index.html is copied with those names
// in place. Source maps only where NHLAB_WEB_SOURCEMAP=1 (the server's build script sets it
// for a debug build). Nothing is fetched from a CDN at run time.

import * as esbuild from 'esbuild';
import { mkdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { basename } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('.', import.meta.url));
const dist = `${root}dist`;

rmSync(dist, { recursive: true, force: true });
mkdirSync(dist);
const built = await esbuild.build({
  absWorkingDir: root,
  entryPoints: { app: 'src/main.js' },
  entryNames: '[name]-[hash]',
  metafile: true,
  bundle: true,
  minify: true,
  sourcemap: process.env.NHLAB_WEB_SOURCEMAP === '1',
  format: 'esm',
  target: ['es2022'],
  outdir: 'dist',
  logLevel: 'warning',
});
// The hashed names in index.html's references to app.js and app.css.
const outputs = Object.keys(built.metafile.outputs).map((p) => basename(p));
const named = (ext) => {
  const found = outputs.find((f) => f.startsWith('app-') && f.endsWith(ext));
  if (!found) throw new Error(`esbuild wrote no app-*${ext}`);
  return found;
};
let html = readFileSync(`${root}src/index.html`, 'utf8');
for (const ext of ['.js', '.css']) {
  const plain = `"app${ext}"`;
  if (!html.includes(plain)) throw new Error(`index.html does not reference ${plain}`);
  html = html.replace(plain, `"${named(ext)}"`);
}
writeFileSync(`${dist}/index.html`, html);
