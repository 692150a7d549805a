#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# clang-format over the C++ sources and headers, with the repository's .clang-format
# (CONTRIBUTING.md "Formatting"):
#   scripts/format.sh           rewrites the files in place
#   scripts/format.sh --check   lists every file whose formatting drifts, exits 1 when any does
# Files: the tracked and untracked-but-not-ignored .cpp and .h files outside the build folders.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
mode="${1:-}"
case "$mode" in
  ""|--check) ;;
  *) echo "usage: format.sh [--check]" >&2; exit 2 ;;
esac
fmt="${CLANG_FORMAT:-clang-format}"
if ! command -v "$fmt" >/dev/null 2>&1; then
  echo "format.sh: $fmt not found (scripts/install-deps.sh installs clang-format)" >&2
  exit 2
fi
cd "$root"
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  files="$(git ls-files --cached --others --exclude-standard -- '*.cpp' '*.h')"
else
  files="$(find . \( -path './build*' -o -path ./out \) -prune -o -type f \( -name '*.cpp' -o -name '*.h' \) -print | sed 's|^\./||')"
fi
files="$(printf '%s\n' "$files" | grep -v -E '^(build[^/]*|out)/' | sort)"
if [ "$mode" = "--check" ]; then
  drift=0
  while IFS= read -r f; do
    [ -n "$f" ] || continue
    if ! "$fmt" --dry-run --Werror "$f" >/dev/null 2>&1; then
      echo "format drift: $f (run scripts/format.sh)"
      drift=$((drift + 1))
    fi
  done <<< "$files"
  n="$(printf '%s\n' "$files" | grep -c . || true)"
  if [ "$drift" -gt 0 ]; then
    echo "format.sh: $drift of $n files differ from .clang-format"
    exit 1
  fi
  echo "format.sh: $n files match .clang-format ($("$fmt" --version | sed 's/.*version //'))"
  exit 0
fi
printf '%s\n' "$files" | xargs -r "$fmt" -i
