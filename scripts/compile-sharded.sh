#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# A sharded compile on this machine (docs/sharded-compile.md): N navmap-compile jobs with
# --shard K/N side by side (xargs, NAVMAP_JOBS at a time, default nproc), then one --merge into OUT.
#   scripts/compile-sharded.sh N OUT --osm region.osm.pbf --dem N42E001.hgt [other navmap-compile options]
# The shard stores and their logs go to OUT.shards/, removed after a successful merge unless
# NAVMAP_KEEP_SHARDS=1. A failed job stops the merge: its log's end is printed and the exit
# status is 1. navmap-compile: $NAVMAP_COMPILE, else build/map/navmap-compile, else the one on PATH.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
# shellcheck source=scripts/shard-args.sh
. "$root/scripts/shard-args.sh"
shard_args "$0" "$@"
shift 2
jobs="${NAVMAP_JOBS:-$(nproc)}"
parts="$out.shards"
rm -rf "$parts"
mkdir -p "$parts"

start=$SECONDS
export compile n parts
# One job: shard K of N into $parts/part-K.navmap (what one task of a batch engine runs).
job() {
  "$compile" -q "$@" --shard "$K/$n" --out "$parts/part-$K.navmap" >"$parts/part-$K.log" 2>&1 \
    || { echo "shard $K/$n failed:" >&2; tail -n 5 "$parts/part-$K.log" >&2; return 1; }
}
export -f job
echo "compile-sharded: $n shards, $jobs at a time, into $parts/"
if ! seq 0 $((n - 1)) | xargs -P "$jobs" -I{} env K={} bash -c 'job "$@"' job "$@"; then
  echo "compile-sharded: a shard failed; nothing merged (logs: $parts/)" >&2
  exit 1
fi
echo "compile-sharded: shards done in $((SECONDS - start)) s"
stores=()
for k in $(seq 0 $((n - 1))); do stores+=("$parts/part-$k.navmap"); done
"$compile" --merge "${stores[@]}" --out "$out"
[ "${NAVMAP_KEEP_SHARDS:-0}" = 1 ] || rm -rf "$parts"
echo "compile-sharded: $out in $((SECONDS - start)) s"
