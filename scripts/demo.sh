#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The main job on a fresh Debian 12 clone: installs what is missing, builds into build/ (which
# compiles the embedded Andorra data into build/andorra.navmap), then runs the navmapd daemon
# with a simulated drive from Andorra la Vella to Encamp, records frames with navmap-view (the
# client a cluster or HUD process would use) and serves the live view to a browser.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
scripts/install-deps.sh --demo
NAVMAP_BUILD_DIR="$root/build" scripts/build.sh -DNAVMAP_WITH_TESTS=OFF -DNAVMAP_WITH_BENCH=OFF >/tmp/navmap-demo-build.log 2>&1 \
  || { tail -n 40 /tmp/navmap-demo-build.log; echo "demo: build failed (log: /tmp/navmap-demo-build.log)" >&2; exit 1; }
echo "demo: built into build/ (log: /tmp/navmap-demo-build.log)"

run="$root/out/run"
rm -rf "$run" out/frames
mkdir -p "$run" out/frames
port="${NAVMAP_DEMO_HTTP_PORT:-8080}"
seconds="${NAVMAP_DEMO_SECONDS:-40}"
build/daemon/navmapd --input sim --speed "${NAVMAP_DEMO_SPEED:-4}" --run-for "$seconds" \
  --control-socket "$run/control.sock" --frame-socket "$run/frames.sock" --http-port "$port" "$@" \
  2> >(tee "$run/navmapd.log" >&2) &
daemon=$!
for _ in $(seq 100); do [ -S "$run/frames.sock" ] && break; sleep 0.1; done
[ -S "$run/frames.sock" ] || { echo "demo: navmapd did not start (log: $run/navmapd.log)" >&2; exit 1; }
echo "demo: navmapd is running (pid $daemon) for $seconds s"
echo "demo: live view in a browser: http://127.0.0.1:$port/   (status: /status, metrics: /metrics)"

# Two recording clients, as the instrument cluster and the center display would connect.
build/ipc/client/navmap-view --unix "$run/frames.sock" --profile cluster --frames 120 \
  --save out/frames/cluster --save-count 120 &
cluster=$!
build/ipc/client/navmap-view --unix "$run/frames.sock" --profile hud --frames 60 \
  --save out/frames/hud --save-count 60 &
hud=$!
build/ipc/client/navmap-view --unix "$run/frames.sock" --profile center --frames 60 \
  --save out/frames/center --save-count 60
wait "$cluster" || true
wait "$hud" || true
build/ipc/control/navmap-ctl --socket "$run/control.sock" get_status > "$run/status.json" || true
kill -TERM "$daemon" 2>/dev/null || true
wait "$daemon" || true

cat <<TXT

demo: recorded frames, one folder per display profile:
        $root/out/frames/cluster/   instrument cluster, 1280x480, snail's view
        $root/out/frames/hud/       head-up display, 800x240, guidance view (next turn, route corridor)
        $root/out/frames/center/    center display, 1280x720, bird's-eye
      look at one:   xdg-open "\$(ls out/frames/cluster/*.png | tail -n 1)"   (or any image viewer)
      as a video:    ffmpeg -framerate 10 -pattern_type glob -i 'out/frames/cluster/*.png' cluster.mp4
      daemon log:    $run/navmapd.log    last status: $run/status.json
TXT
