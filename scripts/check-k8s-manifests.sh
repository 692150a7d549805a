#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Checks Kubernetes manifests against the Kubernetes API's schemas without a cluster
# (docs/sharded-compile.md "Kubernetes"):
#   scripts/check-k8s-manifests.sh [FILE ...]     default: docs/sharded-compile.md
# FILE is a YAML file (documents separated by ---) or a Markdown file, whose ```yaml blocks are
# the manifests. Each object is looked up by apiVersion and kind in the npm package
# kubernetes-models (the Kubernetes 1.33 API's OpenAPI schemas) and checked twice:
#   - its validate(): types, integer formats, enums and required fields;
#   - a TypeScript compile (tsc --strict) of the object as the model's interface: the API's schemas
#     allow fields they do not name, where the API server rejects them (strict field validation),
#     so this is what catches an unknown or misspelt field.
# `kubectl --dry-run=client` is no offline check: kubectl asks the API server for its resource
# list and schemas even then. The npm packages (exact versions below) are installed once into
# ${XDG_CACHE_HOME:-~/.cache}/navmap/k8s-validate (NAVMAP_K8S_VALIDATE_DIR).
# Exit status: 0 all valid, 1 an invalid manifest (file, line, object and field named), 2 usage,
# 77 node or npm missing, or npm could not install the packages (the reason is printed).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
me="check-k8s-manifests"
files=("$@")
[ ${#files[@]} -gt 0 ] || files=("$root/docs/sharded-compile.md")
for f in "${files[@]}"; do [ -f "$f" ] || { echo "$me: $f: no such file" >&2; exit 2; }; done
for tool in node npm; do
  command -v "$tool" >/dev/null 2>&1 || { echo "$me: $tool not found (Debian packages nodejs, npm); not checked" >&2; exit 77; }
done

packages=(kubernetes-models@4.5.1 yaml@2.9.1 typescript@5.9.3)
cache="${NAVMAP_K8S_VALIDATE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/navmap/k8s-validate}"
mkdir -p "$cache"
if [ "$(cat "$cache/installed" 2>/dev/null)" != "${packages[*]}" ]; then
  echo "$me: installing ${packages[*]} into $cache"
  [ -f "$cache/package.json" ] || echo '{"private": true}' >"$cache/package.json"
  if ! (cd "$cache" && npm install --no-audit --no-fund --silent --save-exact "${packages[@]}" >"$cache/npm.log" 2>&1); then
    tail -n 5 "$cache/npm.log" >&2
    echo "$me: npm could not install ${packages[*]}; not checked" >&2
    exit 77
  fi
  echo "${packages[*]}" >"$cache/installed"
fi

work="$(mktemp -d "$cache/check.XXXXXX")"
trap 'rm -rf "$work"' EXIT
cd "$work"
NODE_PATH="$cache/node_modules" node - "${files[@]}" <<'EOF'
// Reads the manifests, runs validate() on each object, writes one TypeScript file per object for
// tsc, and lists in objects.json what each file holds.
const fs = require("fs");
const path = require("path");
const YAML = require("yaml");
const objects = [];
let errors = 0;
for (const file of process.argv.slice(2)) {
  const text = fs.readFileSync(file, "utf8");
  const blocks = []; // [first line of the YAML text, text]
  if (/\.md$/.test(file)) {
    const lines = text.split("\n");
    for (let i = 0; i < lines.length; i++) {
      if (lines[i].trim() !== "```yaml") continue;
      const start = i + 1;
      let end = start;
      while (end < lines.length && lines[end].trim() !== "```") end++;
      blocks.push([start + 1, lines.slice(start, end).join("\n")]);
      i = end;
    }
  } else {
    blocks.push([1, text]);
  }
  for (const [firstLine, yamlText] of blocks) {
    const lineCounter = new YAML.LineCounter();
    for (const doc of YAML.parseAllDocuments(yamlText, { lineCounter })) {
      const where = (offset) => `${file}:${firstLine + lineCounter.linePos(offset).line - 1}`;
      const at = where(doc.range[0]);
      if (doc.errors.length > 0) {
        for (const e of doc.errors) console.error(`${where(e.pos[0])}: YAML: ${e.message.split("\n")[0]}`);
        errors++;
        continue;
      }
      const obj = doc.toJS();
      if (obj === null || obj === undefined) continue;
      const name = `${obj.kind} ${obj.metadata && obj.metadata.name}`;
      const [group, version] = String(obj.apiVersion).includes("/") ? obj.apiVersion.split("/") : ["", obj.apiVersion];
      const module = `kubernetes-models/${group ? group + "/" : ""}${version}/${obj.kind}`;
      let Model;
      try {
        Model = require(module)[obj.kind];
      } catch (e) {
        Model = undefined;
      }
      if (typeof Model !== "function") {
        console.error(`${at}: ${name}: no kind ${obj.kind} in apiVersion ${obj.apiVersion}`);
        errors++;
        continue;
      }
      try {
        new Model(obj).validate();
      } catch (e) {
        console.error(`${at}: ${name}: ${e.message}`);
        errors++;
        continue;
      }
      const ts = `object-${objects.length}.ts`;
      fs.writeFileSync(ts, `import type { I${obj.kind} } from "${module}";\n` +
        `export const object: I${obj.kind} = ${JSON.stringify(obj, null, 2)};\n`);
      objects.push({ ts, at, name });
    }
  }
}
if (objects.length === 0 && errors === 0) {
  console.error(`no Kubernetes manifest found in ${process.argv.slice(2).join(", ")}`);
  errors++;
}
fs.writeFileSync("objects.json", JSON.stringify(objects));
process.exit(errors > 0 ? 1 : 0);
EOF
ln -s "$cache/node_modules" node_modules
mapfile -t ts < <(node -e 'for (const o of require("./objects.json")) console.log(o.ts)')
if ! "$cache/node_modules/.bin/tsc" --noEmit --strict --skipLibCheck --moduleResolution node --module commonjs \
    --target es2020 "${ts[@]}" >tsc.log 2>&1; then
  # object-K.ts(L,C): error TS...: message  ->  FILE:LINE: Kind name: message
  node -e '
    const objects = require("./objects.json");
    for (const line of require("fs").readFileSync("tsc.log", "utf8").split("\n")) {
      const m = /^object-(\d+)\.ts\(\d+,\d+\): error TS\d+: (.*)$/.exec(line);
      if (m) console.error(`${objects[m[1]].at}: ${objects[m[1]].name}: ${m[2]}`);
      else if (line.trim()) console.error(line);
    }'
  exit 1
fi
echo "$me: ${#ts[@]} object(s) valid: $(node -e 'console.log(require("./objects.json").map((o) => o.name).join(", "))')"
