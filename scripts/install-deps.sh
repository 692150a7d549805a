#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs the Debian packages navmap needs, by purpose. Idempotent: packages already installed
# are skipped, and apt is not touched at all when nothing is missing. Runs as root, or through
# sudo when available.
#   install-deps.sh          build, run and test (what scripts/test.sh and .ci/run need)
#   install-deps.sh --demo   build and run only (scripts/demo.sh): no test tools, no browser,
#                            no kernel image, no qemu
#   install-deps.sh --cross  the aarch64 cross compiler and qemu-user (scripts/cross-build.sh)
#   install-deps.sh --list-arm64   prints (installs nothing) the arm64 packages of the sysroot
#                            that scripts/arm64-sysroot.sh unpacks for cross-build.sh --daemon
set -euo pipefail

BUILD=(
  # toolchain
  build-essential cmake ninja-build pkg-config
  # EGL + OpenGL ES 3 (Mesa: llvmpipe via the surfaceless platform, any DRM GPU)
  libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri
  # dma-buf frames: buffers from GBM, their DRM fourcc and modifier names
  libgbm-dev libdrm-dev
  # maths, geodesy
  libglm-dev libgeographiclib-dev
  # OpenStreetMap input (libosmium and its PBF/XML codecs), polygon triangulation (CGAL)
  libosmium2-dev libprotozero-dev zlib1g-dev libbz2-dev libexpat1-dev liblz4-dev libcgal-dev libzstd-dev
  # text
  libfreetype-dev libharfbuzz-dev fonts-dejavu-core fonts-droid-fallback
  # config, JSON, command line, streaming, systemd
  libtomlplusplus-dev nlohmann-json3-dev libcli11-dev libturbojpeg0-dev libsystemd-dev
  # image files (OpenImageIO): navmap-view's recorded frames, golden tests, the orthoimage tools
  libopenimageio-dev
  # man pages from the tools' --help (skipped when absent)
  help2man
  # the GStreamer source element navmapsrc (ipc/gst) and the tools and elements its tests run
  libgstreamer1.0-dev libgstreamer-plugins-base1.0-dev gstreamer1.0-tools gstreamer1.0-plugins-base
  gstreamer1.0-plugins-good
  # navmap-wayland: libwayland-client, xdg-shell's XML (wayland-protocols), wayland-scanner
  libwayland-dev wayland-protocols libwayland-bin
)
TEST=(
  # fuzzers (clang), format and lint checks
  clang libclang-rt-14-dev clang-format clang-tidy
  # global rasters and Natural Earth polygons of the synthetic orthoimages: navmap-ortho-train's
  # training data and the tests that measure the shipped network (docs/orthoimage.md)
  marble-qt-data
  # tests and benchmarks (chromium: the browser tests of the live page)
  libgtest-dev libgmock-dev libbenchmark-dev chromium
  # /metrics through the Prometheus client library's parser; Debian packages (cpack, dpkg-shlibdeps)
  python3-prometheus-client dpkg-dev
  # gst-discoverer-1.0: the navmapsrc tests check their WebM file with it
  gstreamer1.0-plugins-base-apps
  # CAN tools (candump/canplayer) and a Debian kernel under qemu for the real SocketCAN (vcan) test
  can-utils qemu-system-x86 linux-image-amd64 busybox-static cpio
  # navmap-wayland on Weston 10's headless backend (desktop shell, ivi-shell with hmi-controller,
  # weston-screenshooter); libweston-10-dev builds the tests' screenshooter module for ivi-shell
  weston libweston-10-dev
)
# qemu-user-static runs the aarch64 programs (qemu-aarch64-static -L <sysroot>, no binfmt).
CROSS=(g++-aarch64-linux-gnu binutils-aarch64-linux-gnu qemu-user-static)
# The arm64 sysroot: BUILD's libraries (not its toolchain, tools or fonts), the C and C++ runtime's
# development files for the cross compiler, the test and benchmark libraries.
ARM64_SYSROOT=(
  libc6-dev libstdc++-12-dev
  libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri libgbm-dev libdrm-dev
  libglm-dev libgeographiclib-dev
  libosmium2-dev libprotozero-dev zlib1g-dev libbz2-dev libexpat1-dev liblz4-dev libcgal-dev libzstd-dev
  libfreetype-dev libharfbuzz-dev
  libtomlplusplus-dev nlohmann-json3-dev libcli11-dev libturbojpeg0-dev libsystemd-dev
  libopenimageio-dev
  libwayland-dev wayland-protocols
  libgtest-dev libgmock-dev libbenchmark-dev
)

case "${1:-}" in
  "") PACKAGES=("${BUILD[@]}" "${TEST[@]}") ;;
  --demo) PACKAGES=("${BUILD[@]}") ;;
  --cross) PACKAGES=(cmake ninja-build pkg-config nlohmann-json3-dev dpkg-dev "${CROSS[@]}") ;;
  --list-arm64) printf '%s\n' "${ARM64_SYSROOT[@]}"; exit 0 ;;
  *) echo "usage: install-deps.sh [--demo | --cross | --list-arm64]" >&2; exit 2 ;;
esac

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q '^install ok installed$'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO=(sudo); else
    echo "install-deps: missing packages (${missing[*]}) and not root; run as root or install sudo" >&2
    exit 1
  fi
fi
echo "install-deps: installing ${#missing[@]} package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" apt-get update -q
"${SUDO[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
