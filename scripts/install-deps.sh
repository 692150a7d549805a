#!/usr/bin/env bash
# Installs every Debian package navmap needs to build, test and run. Idempotent: packages
# already installed are skipped, and apt is not touched at all when nothing is missing.
# Runs as root, or through sudo when available.
set -euo pipefail

PACKAGES=(
  # toolchain
  build-essential cmake ninja-build pkg-config clang libclang-rt-14-dev
  # EGL + OpenGL ES 3 (Mesa: llvmpipe via the surfaceless platform, any DRM GPU)
  libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri
  # maths, geodesy, images
  libglm-dev libgeographiclib-dev libopenimageio-dev
  # OpenStreetMap input (libosmium and its PBF/XML codecs), polygon tessellation
  libosmium2-dev libprotozero-dev zlib1g-dev libbz2-dev libexpat1-dev liblz4-dev libglu1-mesa-dev libzstd-dev
  # text
  libfreetype-dev libharfbuzz-dev fonts-dejavu-core fonts-droid-fallback
  # config, JSON, command line, streaming, systemd
  libtomlplusplus-dev nlohmann-json3-dev libcli11-dev libturbojpeg0-dev libsystemd-dev
  # tests and benchmarks (chromium: the browser test of the live stream page)
  libgtest-dev libgmock-dev libbenchmark-dev chromium
  # CAN tools (candump/canplayer) and a Debian kernel under qemu for the real SocketCAN (vcan) test
  can-utils qemu-system-x86 linux-image-amd64 busybox-static cpio
)

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
