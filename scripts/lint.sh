#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# clang-tidy with the repository's .clang-tidy over the project's translation units in the
# compile database (CONTRIBUTING.md "Lint"):
#   scripts/lint.sh                 every project source in $NAVMAP_BUILD_DIR/compile_commands.json
#   scripts/lint.sh ipc daemon/x.cpp  only the sources under these paths
# Prints every warning once (a header's warning is reported by each file including it) and their
# count; exits 1 when there is any, 2 when it cannot run. Jobs: NAVMAP_LINT_JOBS (default nproc).
# The database comes from a configure with -DCMAKE_EXPORT_COMPILE_COMMANDS=ON (the top-level
# CMakeLists.txt turns it on); generated sources (shaders) must exist, so build first.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${NAVMAP_BUILD_DIR:-$root/build}"
tidy="${CLANG_TIDY:-clang-tidy}"
jobs="${NAVMAP_LINT_JOBS:-$(nproc)}"
db="$build/compile_commands.json"
if ! command -v "$tidy" >/dev/null 2>&1; then
  echo "lint.sh: $tidy not found (scripts/install-deps.sh installs clang-tidy)" >&2
  exit 2
fi
if [ ! -f "$db" ]; then
  echo "lint.sh: $db: no such file (configure with -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)" >&2
  exit 2
fi
# The project's sources in the database: not the generated ones under the build folder.
files="$(python3 - "$db" "$root" "$build" "$@" <<'EOF'
import json, os, sys
db, root, build, *only = sys.argv[1:]
root = os.path.realpath(root); build = os.path.realpath(build)
only = [os.path.realpath(p) for p in only]
seen = set()
for entry in json.load(open(db)):
    f = os.path.realpath(os.path.join(entry["directory"], entry["file"]))
    if not f.startswith(root + "/") or f.startswith(build + "/") or f in seen:
        continue
    if only and not any(f == p or f.startswith(p + "/") for p in only):
        continue
    seen.add(f)
    print(f)
EOF
)"
if [ -z "$files" ]; then
  echo "lint.sh: no project source in $db matches ${*:-the tree}" >&2
  exit 2
fi
out="$(mktemp)"
trap 'rm -f "$out"' EXIT
start=$SECONDS
# The database is GCC's: clang does not know some of its warning options.
printf '%s\n' "$files" |
  xargs -P "$jobs" -I{} "$tidy" -p "$build" --quiet --extra-arg=-Wno-unknown-warning-option {} \
    2>/dev/null >>"$out" || true
# One line per distinct warning, with its notes dropped (the location and the check say enough).
warnings="$(grep -E '^[^ ].*:[0-9]+:[0-9]+: (warning|error): ' "$out" | sort -u || true)"
count=0
[ -z "$warnings" ] || count="$(printf '%s\n' "$warnings" | wc -l)"
[ -z "$warnings" ] || printf '%s\n' "$warnings"
echo "lint.sh: $count warning(s) in $(printf '%s\n' "$files" | wc -l) translation unit(s), $((SECONDS - start)) s"
[ "$count" -eq 0 ]
