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
build/daemon/navmapd --frames "${NAVMAP_DEMO_FRAMES:-60}" --sim-step 2 --profiles cluster,center --out out/frames "$@"
cat <<TXT

demo: the frames are PNG files, one folder per display profile:
        $root/out/frames/cluster/   instrument cluster, 1280x480, snail's view
        $root/out/frames/center/    center display, 1280x720, bird's-eye
      look at one:   xdg-open out/frames/cluster/frame_0030.png   (or any image viewer)
      as a video:    ffmpeg -framerate 10 -i out/frames/cluster/frame_%04d.png cluster.mp4
TXT
