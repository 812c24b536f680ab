// Builds the page into dist/ (what the nhlab binary embeds): esbuild bundles src/main.js with
// uPlot and eventsource-parser into app.js, their CSS into app.css; index.html is copied.
// Nothing is fetched from a CDN at run time.

import * as esbuild from 'esbuild';
import { copyFileSync, mkdirSync, rmSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('.', import.meta.url));
const dist = `${root}dist`;

rmSync(dist, { recursive: true, force: true });
mkdirSync(dist);
await esbuild.build({
  absWorkingDir: root,
  entryPoints: { app: 'src/main.js' },
  bundle: true,
  minify: true,
  sourcemap: true,
  format: 'esm',
  target: ['es2022'],
  outdir: 'dist',
  logLevel: 'warning',
});
copyFileSync(`${root}src/index.html`, `${dist}/index.html`);
