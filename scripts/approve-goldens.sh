#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Approves new golden images: copies every <build>/golden-failures/<name>.actual.png over the
# golden it was compared with (named in <name>.target). Look at the actual and diff images
# first. Usage: scripts/approve-goldens.sh [build-dir]   (default: build)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
dir="$build/golden-failures"
shopt -s nullglob
targets=("$dir"/*.target)
if [ ${#targets[@]} -eq 0 ]; then
  echo "approve-goldens: nothing to approve in $dir (run the tests first)"
  exit 0
fi
for t in "${targets[@]}"; do
  name="$(basename "$t" .target)"
  golden="$root/$(head -n1 "$t")"
  mkdir -p "$(dirname "$golden")"
  cp "$dir/$name.actual.png" "$golden"
  rm -f "$t" "$dir/$name.actual.png" "$dir/$name.diff.png"
  echo "approved: ${golden#$root/}"
done
