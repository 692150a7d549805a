#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# scripts/compile-sharded.sh on the Andorra data: the merge of 2 shards run side by side is the
# default store byte for byte (both are compiled with navmap-compile's defaults), the shard files
# are cleaned up, and a failing job leaves no store and exits 1.
#   compile_sharded_test.sh <navmap-compile> <default store> <source dir>
set -euo pipefail
compile="$1" store="$2" src="$3"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
NAVMAP_COMPILE="$compile" "$src/scripts/compile-sharded.sh" 2 "$tmp/merged.navmap" \
  --osm "$src/data/andorra-2021-04-14.osm.pbf" --dem "$src/data/N42E001.hgt" >"$tmp/log" 2>&1 \
  || { cat "$tmp/log"; echo "FAIL: the sharded compile failed"; exit 1; }
cmp "$tmp/merged.navmap" "$store" || { echo "FAIL: the merged store differs from $store"; exit 1; }
[ ! -e "$tmp/merged.navmap.shards" ] || { echo "FAIL: shard files left in $tmp/merged.navmap.shards"; exit 1; }
status=0
NAVMAP_COMPILE="$compile" "$src/scripts/compile-sharded.sh" 2 "$tmp/bad.navmap" --osm "$tmp/missing.pbf" \
  >"$tmp/bad.log" 2>&1 || status=$?
[ "$status" = 1 ] || { cat "$tmp/bad.log"; echo "FAIL: a failing shard should exit 1, not $status"; exit 1; }
[ ! -e "$tmp/bad.navmap" ] || { echo "FAIL: a store was written after a failed shard"; exit 1; }
grep -q "missing.pbf): No such file or directory (OSM input)" "$tmp/bad.log" || { cat "$tmp/bad.log"; echo "FAIL: the job's error is not shown"; exit 1; }
echo "compile-sharded: 2 shards merged = $store, byte for byte; a failed shard stops the merge"
