#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# A drive that crosses navmapd's frame re-centring (docs/navmapd.md "Map frame"): the Andorra store
# and a copy of it 0.25 degrees (28 km) north, mounted together; a replayed GNSS log drives north
# at 30 m/s from the south of Andorra into the copy, through the point where the frame's scale is
# 0.5 % off and the frame moves onto the vehicle. A second run drives only the part before that
# point (no re-centring). Prints one JSON line per run: frames received, frames/s and the longest
# wait between two frames as the cluster client saw it, the re-centrings and their reload times.
#   bench/daemon/recentre_drive.sh build [speed]
set -euo pipefail
build="$(cd "${1:?usage: recentre_drive.sh BUILD_DIR [SPEED]}" && pwd)"
speed="${2:-8}"
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="${NAVMAP_RECENTRE_DIR:-/tmp/navmap-recentre}"
rm -rf "$work"
mkdir -p "$work/next"
# shellcheck disable=SC2207
args=($("$build/map/navmap-synth-region" -q --osm "$root/data/andorra-2021-04-14.osm.pbf" \
  --dem "$root/data/N42E001.hgt" --shift-lat 0.25 --out-dir "$work/next"))
"$build/map/navmap-compile" "${args[@]}" --out "$work/next.navmap" > /dev/null 2>&1
# GNSS fixes at 10 Hz (the navmap GNSS node, data/navmap.dbc), 3 m apart, heading north.
drive() {
  python3 - "$1" "$2" "$3" <<'PY'
import struct, sys
lat, end, out = float(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
lines, n, t = [], 0, 1618394400.0
while lat < end:
    pos = struct.pack('<ii', round(lat * 1e7), round(1.5219 * 1e7)).hex().upper()
    lines.append("(%.6f) vcan0 6A0#%s\n" % (t, pos))
    lines.append("(%.6f) vcan0 6A1#000000000000%02X09\n" % (t + 0.001, 3 | ((n & 15) << 4)))
    n, t, lat = n + 1, t + 0.1, lat + 3.0 / 111000.0
open(out, 'w').writelines(lines)
PY
}
run() {
  local name="$1" end="$2"
  local dir="$work/$name"
  mkdir -p "$dir"
  drive 42.46 "$end" "$dir/drive.candump"
  local seconds
  # The client watches the drive once (the replay loops back to the start after it).
  seconds=$(python3 -c "print(int((($end - 42.46) * 111000 / 30) / $speed) - 1)")
  "$build/daemon/navmapd" --store "$build/share/navmap/andorra.navmap" --mount "$work/next.navmap" \
    --replay "$dir/drive.candump" --speed "$speed" --control-socket "$dir/c.sock" --frame-socket "$dir/f.sock" \
    --http-port 0 --profiles cluster --no-labels --log-level info --run-for "$((seconds + 2))" > "$dir/navmapd.log" 2>&1 &
  local pid=$!
  for _ in $(seq 100); do [ -S "$dir/f.sock" ] && break; sleep 0.1; done
  local view
  view=$("$build/ipc/client/navmap-view" --unix "$dir/f.sock" --profile cluster --frames 0 --duration "$seconds" --json 2> /dev/null)
  wait "$pid" || true
  local recentred reload
  recentred=$(grep -c "map frame re-centred" "$dir/navmapd.log" || true)
  reload=$(grep -o "tiles reloaded in [0-9]* ms" "$dir/navmapd.log" | grep -o "[0-9]* ms" | tr '\n' ' ' || true)
  python3 -c "import json,sys; v=json.loads(sys.argv[1]); print(json.dumps({'run': sys.argv[2], 'km': round((float(sys.argv[3]) - 42.46) * 111, 1), 'speed': float(sys.argv[6]), 'frames': v['frames'], 'fps': v['fps'], 'longest_gap_ms': v['longest_gap_ms'], 'recentred': int(sys.argv[4]), 'reload': sys.argv[5].strip()}))" \
    "$view" "$name" "$end" "$recentred" "$reload" "$speed"
}
run before 42.70
run across 42.94
