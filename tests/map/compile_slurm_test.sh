#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The sharded compile on Slurm (scripts/compile-slurm.sh, docs/sharded-compile.md "Slurm"), label
# slurm (opt-in): in a private single-node cluster (scripts/slurm-local.sh; NAVMAP_SLURM=existing
# uses the configured one, with NAVMAP_SLURM_WORKDIR on storage its nodes share), the Andorra
# data as a job array of 3 shards and the merge as a dependent job; the merged store must equal
# the single-process compile byte for byte. Then a job array whose shards fail: the merge is
# cancelled, no store is written, the exit status is 1 and the jobs' error is shown.
#   compile_slurm_test.sh <navmap-compile> <source dir>
set -euo pipefail
compile="$1" src="$2"
if [ "${3:-}" != --in-cluster ]; then
  exec "$src/scripts/slurm-local.sh" "$0" "$compile" "$src" --in-cluster
fi
tmp="$(mktemp -d "${NAVMAP_SLURM_WORKDIR:-${TMPDIR:-/tmp}}/navmap-slurm-test.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
export NAVMAP_COMPILE="$compile" NAVMAP_SLURM_TIMEOUT="${NAVMAP_SLURM_TIMEOUT:-240}"
# Less than the scripts' 8G each, so that the jobs fit a small node.
export NAVMAP_SLURM_ARGS="${NAVMAP_SLURM_ARGS:---mem=1G}"
input=(--osm "$src/data/andorra-2021-04-14.osm.pbf" --dem "$src/data/N42E001.hgt")
"$compile" -q "${input[@]}" --out "$tmp/single.navmap" >"$tmp/single.log" 2>&1 \
  || { cat "$tmp/single.log"; echo "FAIL: the single-process compile failed"; exit 1; }
start=$SECONDS
"$src/scripts/compile-slurm.sh" 3 "$tmp/merged.navmap" "${input[@]}" >"$tmp/log" 2>&1 \
  || { cat "$tmp/log"; echo "FAIL: the sharded compile on Slurm failed"; exit 1; }
cat "$tmp/log"
grep -q "3 shards as job array [0-9]* (0-2), the merge as job [0-9]* (afterok:" "$tmp/log" \
  || { echo "FAIL: no job array and dependent merge reported"; exit 1; }
cmp "$tmp/merged.navmap" "$tmp/single.navmap" \
  || { echo "FAIL: the merged store differs from the single-process compile"; exit 1; }
[ ! -e "$tmp/merged.navmap.shards" ] || { echo "FAIL: shard files left in $tmp/merged.navmap.shards"; exit 1; }
echo "compile-slurm: 3 shards merged in $((SECONDS - start)) s = the single-process compile ($(stat -c %s "$tmp/single.navmap") bytes), byte for byte"

status=0
"$src/scripts/compile-slurm.sh" 2 "$tmp/bad.navmap" --osm "$tmp/missing.pbf" >"$tmp/bad.log" 2>&1 || status=$?
cat "$tmp/bad.log"
[ "$status" = 1 ] || { echo "FAIL: failing shards should exit 1, not $status"; exit 1; }
[ ! -e "$tmp/bad.navmap" ] || { echo "FAIL: a store was written after the shards failed"; exit 1; }
grep -q "the merge was cancelled" "$tmp/bad.log" || { echo "FAIL: the merge's cancellation is not reported"; exit 1; }
[ "$(grep -c "missing.pbf): No such file or directory (OSM input)" "$tmp/bad.log")" = 2 ] \
  || { echo "FAIL: the error of each failed shard is not shown"; exit 1; }
echo "compile-slurm: failed shards cancel the merge (exit 1, no store)"
