#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Runs an aarch64 program of the cross build on this machine: qemu-aarch64-static (Debian's
# qemu-user-static; no binfmt registration) with -L <sysroot>, so that its loader, libraries and
# Mesa's arm64 drivers (llvmpipe, EGL surfaceless) come from the sysroot of scripts/arm64-sysroot.sh.
# The cross build's CMAKE_CROSSCOMPILING_EMULATOR (cmake/toolchains/aarch64-linux-gnu.cmake), so
# CTest and gtest's test discovery run the arm64 test programs through it.
#   qemu-aarch64.sh <sysroot> <program> [args...]
set -euo pipefail
sysroot="${1:?usage: qemu-aarch64.sh <sysroot> <program> [args...]}"
shift
# Mesa's loader and libglvnd open these by absolute path; point them into the sysroot explicitly
# (qemu's -L also redirects paths that exist there, but not a search of the build machine's dirs).
export LIBGL_DRIVERS_PATH="$sysroot/usr/lib/aarch64-linux-gnu/dri"
export __EGL_VENDOR_LIBRARY_DIRS="$sysroot/usr/share/glvnd/egl_vendor.d"
# No GPU is emulated: Mesa's software rasterizer (as in the native gpu tests without a GPU).
export LIBGL_ALWAYS_SOFTWARE=1
export GALLIUM_DRIVER=llvmpipe
exec qemu-aarch64-static -L "$sysroot" "$@"
