#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Cross-compiles navmap for aarch64 (64-bit ARM ECUs) with Debian's g++-aarch64-linux-gnu into
# build-aarch64/ (or $NAVMAP_CROSS_BUILD_DIR) and checks that the results are AArch64 ELF files.
#   scripts/cross-build.sh            libnavmap-client and its C example (-DNAVMAP_WITH_DAEMON=OFF):
#                                     needs only the cross compiler
#   scripts/cross-build.sh --daemon   everything: needs the daemon's arm64 -dev packages, installed
#                                     (multiarch) or unpacked into NAVMAP_SYSROOT (on Debian 12 some
#                                     cannot be installed beside the amd64 ones: docs/packaging.md),
#                                     and a native build's navmap-compile (NAVMAP_HOST_TOOLS, default
#                                     build/NavmapHostTools.cmake)
# Opt-in (CTest label `cross`; not in scripts/test.sh or .ci/run): docs/packaging.md says why.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${NAVMAP_CROSS_BUILD_DIR:-$root/build-aarch64}"
daemon=OFF
if [ "${1:-}" = "--daemon" ]; then daemon=ON; shift; fi
"$root/scripts/install-deps.sh" --cross
args=(-DCMAKE_TOOLCHAIN_FILE="$root/cmake/toolchains/aarch64-linux-gnu.cmake" -DNAVMAP_WITH_DAEMON=$daemon
      -DNAVMAP_WITH_TESTS=OFF -DNAVMAP_WITH_BENCH=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo)
if [ "$daemon" = ON ]; then
    args+=(-DNAVMAP_HOST_TOOLS="${NAVMAP_HOST_TOOLS:-$root/build/NavmapHostTools.cmake}")
fi
generator=()
if command -v ninja >/dev/null 2>&1 && [ ! -f "$build/Makefile" ]; then generator=(-G Ninja); fi
cmake -S "$root" -B "$build" "${generator[@]}" "${args[@]}" "$@"
cmake --build "$build" -j "$(nproc)"
status=0
check() {
    local f="$build/$1"
    if [ ! -f "$f" ]; then echo "cross-build: missing $1" >&2; status=1; return; fi
    local machine
    machine="$(readelf -h "$f" | sed -n 's/^ *Machine: *//p')"
    echo "cross-build: $1: $machine; needs: $(readelf -d "$f" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' | tr '\n' ' ')"
    [ "$machine" = "AArch64" ] || { echo "cross-build: $1 is not AArch64" >&2; status=1; }
}
check ipc/src/stream/libnavmap-client.so.0
check examples/c_client/navmap-client-example
if [ "$daemon" = ON ]; then
    check daemon/navmapd
    check ipc/src/stream/navmap-view
    [ -f "$build/andorra.navmap" ] && echo "cross-build: default store made by the host navmap-compile: $(stat -c %s "$build/andorra.navmap") bytes"
fi
exit $status
