#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Scale runs of navmap-compile (docs/benchmarks/2026-11-26-bounded-compile.md): for each copy
# count, a region made by navmap-synth-region from the Andorra extract under $NAVMAP_SCALE_DIR
# (default /tmp/navmap-scale), compiled in memory and with --memory-limit LIMIT_MIB. Prints one
# markdown table row per compile (wall seconds, peak RSS, its anonymous and file-backed parts,
# store size, bands) and whether the two
# stores are byte-identical. Keeps the regions (delete $NAVMAP_SCALE_DIR afterwards).
#   bench/map/compile_scale.sh build 256 1 10 100
# NAVMAP_SCALE_SKIP_MEMORY="100" leaves out the in-memory compile of those copy counts;
# NAVMAP_SCALE_CLEAN=1 removes each region once compiled. Exit status 1 when a bounded store
# differs from the in-memory one (the soak test compile_bounded_10x runs it so).
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: compile_scale.sh BUILD_DIR LIMIT_MIB COPIES..." >&2
  exit 2
fi
build="$(cd "$1" && pwd)"
limit="$2"
shift 2
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="${NAVMAP_SCALE_DIR:-/tmp/navmap-scale}"
mkdir -p "$work"
status=0
echo "| copies | input .osm.pbf | compile | wall s | peak RSS MiB | peak anon / file MiB | store MB | tiles | bands |"
echo "|---|---|---|---|---|---|---|---|---|"
for n in "$@"; do
  dir="$work/r$n"
  rm -rf "$dir"
  mkdir -p "$dir"
  # shellcheck disable=SC2207
  args=($("$build/map/navmap-synth-region" -q --osm "$root/data/andorra-2021-04-14.osm.pbf" \
    --dem "$root/data/N42E001.hgt" --copies "$n" --out-dir "$dir"))
  input_mb=$(awk "BEGIN { printf \"%.1f MB\", $(stat -c %s "$dir/region.osm.pbf") / 1e6 }")
  for mode in memory bounded; do
    extra=()
    if [ "$mode" = bounded ]; then
      extra=(--memory-limit "$limit" --spill-dir "$dir")
    elif [[ " ${NAVMAP_SCALE_SKIP_MEMORY:-} " == *" $n "* ]]; then
      continue
    fi
    /usr/bin/time -f "%e %M" -o "$dir/$mode.time" "$build/map/navmap-compile" "${args[@]}" "${extra[@]}" \
      --out "$dir/$mode.navmap" > "$dir/$mode.log" 2>&1 &
    time_pid=$!
    # Peak anonymous and file-backed resident memory (the mapped node index is file-backed),
    # sampled twice a second from /proc.
    anon_kb=0
    file_kb=0
    while kill -0 "$time_pid" 2>/dev/null; do
      pid=$(pgrep -P "$time_pid" || true)
      if [ -n "$pid" ] && [ -r "/proc/$pid/status" ]; then
        read -r a f < <(awk '/^RssAnon/ {a = $2} /^RssFile/ {f = $2} END {print a + 0, f + 0}' "/proc/$pid/status" 2>/dev/null || echo "0 0")
        [ "$a" -gt "$anon_kb" ] && anon_kb=$a
        [ "$f" -gt "$file_kb" ] && file_kb=$f
      fi
      sleep 0.5
    done
    wait "$time_pid"
    read -r secs rss_kb < "$dir/$mode.time"
    store_mb=$(awk "BEGIN { printf \"%.1f\", $(stat -c %s "$dir/$mode.navmap") / 1e6 }")
    tiles=$(sed -n 's/^tiles: *\([0-9]*\).*/\1/p' "$dir/$mode.log")
    bands=$(sed -n 's/.*; \([0-9]*\) band(s)$/\1/p' "$dir/$mode.log")
    label="in memory"
    [ "$mode" = bounded ] && label="--memory-limit $limit"
    echo "| $n | $input_mb | $label | $secs | $((rss_kb / 1024)) | $((anon_kb / 1024)) / $((file_kb / 1024)) | $store_mb | $tiles | ${bands:--} |"
  done
  if [ -f "$dir/memory.navmap" ]; then
    if cmp -s "$dir/memory.navmap" "$dir/bounded.navmap"; then
      echo "<!-- $n copies: the two stores are byte-identical -->"
    else
      echo "<!-- $n copies: the stores DIFFER -->"
      status=1
    fi
  fi
  rm -f "$dir"/*.hgt "$dir/memory.navmap"
  if [ "${NAVMAP_SCALE_CLEAN:-0}" = 1 ]; then rm -rf "$dir"; fi
done
if [ "${NAVMAP_SCALE_CLEAN:-0}" = 1 ]; then rmdir "$work" 2>/dev/null || true; fi
exit $status
