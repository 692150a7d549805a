#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Configures and builds navmap into build/ (or $NAVMAP_BUILD_DIR). Extra arguments go to the
# CMake configure step. Used by demo.sh and test.sh.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${NAVMAP_BUILD_DIR:-$root/build}"
generator=()
if command -v ninja >/dev/null 2>&1 && [ ! -f "$build/Makefile" ]; then generator=(-G Ninja); fi
cmake -S "$root" -B "$build" "${generator[@]}" "$@"
cmake --build "$build" -j "$(nproc)"
