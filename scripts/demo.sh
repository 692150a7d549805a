#!/usr/bin/env bash
# The main job on a fresh Debian 12 clone: installs what is missing, builds into build/, and runs
# navmapd on the embedded default data (SRTM heightfield of Andorra), writing a fly-over of
# frames to out/frames/.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
scripts/install-deps.sh
NAVMAP_BUILD_DIR="$root/build" scripts/build.sh -DNAVMAP_WITH_TESTS=OFF -DNAVMAP_WITH_BENCH=OFF >/tmp/navmap-demo-build.log 2>&1 \
  || { tail -n 40 /tmp/navmap-demo-build.log; echo "demo: build failed (log: /tmp/navmap-demo-build.log)" >&2; exit 1; }
echo "demo: built into build/ (log: /tmp/navmap-demo-build.log)"
rm -rf out/frames
build/daemon/navmapd --frames "${NAVMAP_DEMO_FRAMES:-24}" --out out/frames "$@"
cat <<TXT

demo: the frames are PNG files in $root/out/frames/
      look at one:   xdg-open out/frames/frame_0000.png   (or any image viewer)
      as a video:    ffmpeg -framerate 12 -i out/frames/frame_%04d.png andorra.mp4
TXT
