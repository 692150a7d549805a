#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Cross-compiles navmap for aarch64 (64-bit ARM ECUs) with Debian's g++-aarch64-linux-gnu into
# build-aarch64/ (or $NAVMAP_CROSS_BUILD_DIR) and checks that the results are AArch64 ELF files.
#   scripts/cross-build.sh            libnavmap-client and its C example (-DNAVMAP_WITH_DAEMON=OFF):
#                                     needs only the cross compiler
#   scripts/cross-build.sh --daemon   everything (navmapd, the tools, the client, the tests and the
#                                     benchmarks) against an arm64 sysroot of Debian packages that
#                                     scripts/arm64-sysroot.sh makes and caches (NAVMAP_SYSROOT
#                                     given: that one), with the default store made by a native
#                                     build's navmap-compile (NAVMAP_HOST_TOOLS, default
#                                     build/NavmapHostTools.cmake). Prints NAVMAP_SYSROOT=<path>.
# Further arguments go to cmake's configure. NAVMAP_CROSS_TARGETS (default: all) names the targets
# to build; NAVMAP_CROSS_JOBS the parallel jobs (default: nproc).
# The arm64 programs run under qemu-aarch64-static (scripts/qemu-aarch64.sh, CTest's emulator):
# label `arm64`, docs/packaging.md "Cross-compiling for aarch64".
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${NAVMAP_CROSS_BUILD_DIR:-$root/build-aarch64}"
daemon=OFF
if [ "${1:-}" = "--daemon" ]; then daemon=ON; shift; fi
"$root/scripts/install-deps.sh" --cross
args=(-DCMAKE_TOOLCHAIN_FILE="$root/cmake/toolchains/aarch64-linux-gnu.cmake" "-DNAVMAP_WITH_DAEMON=$daemon"
      -DCMAKE_BUILD_TYPE=RelWithDebInfo)
if command -v ccache >/dev/null 2>&1; then
    args+=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
if [ "$daemon" = ON ]; then
    if [ -z "${NAVMAP_SYSROOT:-}" ]; then
        NAVMAP_SYSROOT="$("$root/scripts/arm64-sysroot.sh" | sed -n 's/^NAVMAP_SYSROOT=//p')"
    fi
    [ -f "$NAVMAP_SYSROOT/lib/ld-linux-aarch64.so.1" ] || [ -L "$NAVMAP_SYSROOT/lib/ld-linux-aarch64.so.1" ] ||
        { echo "cross-build: NAVMAP_SYSROOT='$NAVMAP_SYSROOT' is not an arm64 sysroot" >&2; exit 1; }
    echo "NAVMAP_SYSROOT=$NAVMAP_SYSROOT"
    # Installing (cpack) takes what was built: NAVMAP_CROSS_TARGETS may leave out the tests.
    args+=(-DNAVMAP_SYSROOT="$NAVMAP_SYSROOT" -DNAVMAP_WITH_TESTS=ON -DNAVMAP_WITH_BENCH=ON
           -DNAVMAP_HOST_TOOLS="${NAVMAP_HOST_TOOLS:-$root/build/NavmapHostTools.cmake}"
           -DCMAKE_SKIP_INSTALL_ALL_DEPENDENCY=ON)
else
    args+=(-DNAVMAP_WITH_TESTS=OFF -DNAVMAP_WITH_BENCH=OFF)
fi
generator=()
if command -v ninja >/dev/null 2>&1 && [ ! -f "$build/Makefile" ]; then generator=(-G Ninja); fi
cmake -S "$root" -B "$build" "${generator[@]}" "${args[@]}" "$@"
if [ "$daemon" = ON ]; then
    # <build>/arm64-run <program> [args]: an arm64 program of this tree under qemu with the sysroot.
    printf '#!/bin/sh\n# Made by scripts/cross-build.sh --daemon\nexec "%s" "%s" "$@"\n' \
        "$root/scripts/qemu-aarch64.sh" "$NAVMAP_SYSROOT" >"$build/arm64-run"
    chmod +x "$build/arm64-run"
fi
read -r -a targets <<<"${NAVMAP_CROSS_TARGETS:-all}"
cmake --build "$build" -j "${NAVMAP_CROSS_JOBS:-$(nproc)}" --target "${targets[@]}"
[ "${NAVMAP_CROSS_TARGETS:-all}" = all ] || exit 0
status=0
check() {
    local f="$build/$1"
    if [ ! -f "$f" ]; then echo "cross-build: missing $1" >&2; status=1; return; fi
    local machine
    machine="$(readelf -h "$f" | sed -n 's/^ *Machine: *//p')"
    echo "cross-build: $1: $machine; needs: $(readelf -d "$f" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' | tr '\n' ' ')"
    [ "$machine" = "AArch64" ] || { echo "cross-build: $1 is not AArch64" >&2; status=1; }
}
check ipc/client/libnavmap-client.so.0
check examples/c_client/navmap-client-example
if [ "$daemon" = ON ]; then
    check daemon/navmapd
    check ipc/client/navmap-view
    check map/navmap-compile
    check tests/common/common_check_test
    [ -f "$build/andorra.navmap" ] && echo "cross-build: default store made by the host navmap-compile: $(stat -c %s "$build/andorra.navmap") bytes"
fi
exit $status
