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
  # One clang-format per batch of files (not per file): --dry-run --Werror names each file that
  # would change as "<file>:<line>:<col>: error: code should be clang-formatted".
  rc=0
  report="$(printf '%s\n' "$files" | xargs -r "$fmt" --dry-run --Werror 2>&1 >/dev/null)" || rc=$?
  drifted="$(printf '%s\n' "$report" | sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: error: code should be clang-formatted.*/\1/p' | sort -u)"
  n="$(printf '%s\n' "$files" | grep -c . || true)"
  if [ -n "$drifted" ]; then
    while IFS= read -r f; do echo "format drift: $f (run scripts/format.sh)"; done <<< "$drifted"
    echo "format.sh: $(printf '%s\n' "$drifted" | grep -c .) of $n files differ from .clang-format"
    exit 1
  fi
  if [ "$rc" -ne 0 ]; then
    printf '%s\n' "$report" >&2
    echo "format.sh: $fmt failed (exit $rc)" >&2
    exit 2
  fi
  echo "format.sh: $n files match .clang-format ($("$fmt" --version | sed 's/.*version //'))"
  exit 0
fi
printf '%s\n' "$files" | xargs -r "$fmt" -i
