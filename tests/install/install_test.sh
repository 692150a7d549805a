#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The installed tree as an HMI integrator gets it (CTest `install_tree`, label install):
#   1. `cmake --install` into a fresh prefix puts every part in its FHS place under the prefix;
#   2. no installed binary contains a path of the build machine (source or build tree);
#   3. the installed navmapd runs from the prefix alone (store, DBC) and so does a moved copy;
#   4. a copy of examples/c_client, configured with CMAKE_PREFIX_PATH only, builds against the
#      installed CMake package (find_package(navmap COMPONENTS client)) and receives frames from
#      the installed navmapd; pkg-config builds a C and a C++ client as well.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR MAN_PAGES(ON|OFF)
set -euo pipefail
build="$1"
src="$2"
man="$3"
work="$(mktemp -d /tmp/navmap-install-test.XXXXXX)"
daemon=""
cleanup() {
    if [ -n "$daemon" ]; then kill -TERM "$daemon" 2>/dev/null || true; wait "$daemon" 2>/dev/null || true; fi
    rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" > "$work/install.log" || { cat "$work/install.log"; fail "cmake --install"; }
libdir=""
for candidate in "$prefix"/lib/libnavmap-client.so.0 "$prefix"/lib/*/libnavmap-client.so.0; do
    if [ -e "$candidate" ]; then libdir="$(dirname "${candidate#"$prefix"/}")"; break; fi
done
[ -n "$libdir" ] || fail "no libnavmap-client.so.0 under $prefix/lib"
echo "installed into $prefix (libdir $libdir):"
expected=(
    bin/navmapd bin/navmap-view bin/navmap-ctl bin/navmap-compile bin/navmap-sim bin/navmap-soak
    share/navmap/andorra.navmap share/navmap/navmap.dbc share/navmap/ortho-mlp.nnw share/navmap/ATTRIBUTION.md
    etc/navmap/navmapd.toml lib/systemd/system/navmapd.service lib/sysusers.d/navmap.conf
    share/doc/navmap/navmapd.md share/doc/navmap/frame-protocol.md share/doc/navmap/LICENSE
    share/doc/navmap/CHANGELOG.md share/doc/navmap/ATTRIBUTION.md
    include/navmap_client.h include/navmap/version.h include/navmap/ipc/client/stream_client.h
    include/navmap/ipc/client/reconnecting_client.h include/navmap/ipc/net/result.h
    "$libdir/libnavmap-client.so" "$libdir/libnavmap-client.so.0" "$libdir/cmake/navmap/navmapConfig.cmake"
    "$libdir/cmake/navmap/navmapConfigVersion.cmake" "$libdir/cmake/navmap/navmapClientTargets.cmake"
    "$libdir/pkgconfig/navmap-client.pc"
)
if [ "$man" = ON ]; then
    expected+=(share/man/man1/navmapd.1 share/man/man1/navmap-view.1 share/man/man1/navmap-ctl.1
               share/man/man1/navmap-compile.1 share/man/man1/navmap-sim.1 share/man/man1/navmap-soak.1)
fi
# navmap-wayland unless the build left it out (-DNAVMAP_WITH_WAYLAND=OFF).
if ! grep -q '^NAVMAP_WITH_WAYLAND:BOOL=OFF$' "$build/CMakeCache.txt"; then
    expected+=(bin/navmap-wayland)
    if [ "$man" = ON ]; then expected+=(share/man/man1/navmap-wayland.1); fi
fi
for f in "${expected[@]}"; do
    [ -e "$prefix/$f" ] || fail "missing $f"
done
(cd "$prefix" && find . -type f -o -type l | sort | sed 's/^\.\//  /')
# Nothing in the tree is a shader read at run time: they are compiled into navmapd.
if [ -n "$(find "$prefix" -name '*.vert' -o -name '*.frag' -o -name '*.glsl')" ]; then fail "shader files installed"; fi
grep -qx "ExecStart=$prefix/bin/navmapd --config $prefix/etc/navmap/navmapd.toml" "$prefix/lib/systemd/system/navmapd.service" \
    || fail "the unit does not name this prefix: $(grep ExecStart "$prefix/lib/systemd/system/navmapd.service")"
grep -q '^u navmap ' "$prefix/lib/sysusers.d/navmap.conf" || fail "sysusers.d entry has no navmap user"

# The GStreamer plugin (NAVMAP_WITH_GSTREAMER) in GStreamer's directory under the prefix; it finds
# the installed libnavmap-client relative to itself.
plugin=()
if [ -f "$build/gstreamer-1.0/libgstnavmap.so" ]; then
    for f in "$prefix"/lib/*/gstreamer-1.0/libgstnavmap.so "$prefix"/lib/gstreamer-1.0/libgstnavmap.so; do
        if [ -f "$f" ]; then plugin=("$f"); break; fi
    done
    [ "${#plugin[@]}" -eq 1 ] || fail "missing lib/<multiarch>/gstreamer-1.0/libgstnavmap.so"
    [ -f "$prefix/include/navmap/gst/navmap_frame_meta.h" ] || fail "missing include/navmap/gst/navmap_frame_meta.h"
    if command -v gst-inspect-1.0 > /dev/null; then
        GST_REGISTRY="$work/gst-registry.bin" GST_PLUGIN_PATH="$(dirname "${plugin[0]}")" \
            gst-inspect-1.0 navmapsrc > "$work/gst-inspect.log" 2>&1 || { cat "$work/gst-inspect.log"; fail "gst-inspect-1.0 navmapsrc"; }
        grep -q "Filename *${plugin[0]}" "$work/gst-inspect.log" || fail "navmapsrc was not loaded from the prefix"
    fi
fi

# 2. No path of the build machine in anything installed that runs.
for f in "$prefix"/bin/* "$prefix/$libdir"/libnavmap-client.so.* "${plugin[@]}"; do
    for path in "$src" "$build" "$(dirname "$src")/"; do
        if grep -a -q -F "$path" "$f"; then
            fail "$f contains '$path': $(strings -a "$f" | grep -F "$path" | head -n 3 | tr '\n' ' ')"
        fi
    done
done
echo "no installed binary contains $src, $build or $(dirname "$src")/"

# 3. The installed daemon finds its data under the prefix, also after the tree is moved.
# (Outputs are taken whole before grep: `program | grep -q` under pipefail fails when grep stops
# reading early and the program dies of SIGPIPE.)
grep -qx "navmapd $(sed -n 's/^#define NAVMAP_VERSION "\(.*\)"/\1/p' "$prefix/include/navmap/version.h")" \
    <<< "$("$prefix/bin/navmapd" --version)" || fail "navmapd --version"
grep -qx "store: $prefix/share/navmap/andorra.navmap (cache 128 MiB)" <<< "$("$prefix/bin/navmapd" --check-config)" \
    || fail "the default store is not the installed one: $("$prefix/bin/navmapd" --check-config | grep store)"
mv "$prefix" "$work/moved"
grep -qx "store: $work/moved/share/navmap/andorra.navmap (cache 128 MiB)" \
    <<< "$("$work/moved/bin/navmapd" --check-config)" || fail "a moved tree still looks for its data in the old place"
mv "$work/moved" "$prefix"
sock="$work/frames.sock"
"$prefix/bin/navmapd" --noop --input sim --run-for 60 --control-socket "$work/control.sock" --frame-socket "$sock" \
    --log-level notice > "$work/navmapd.log" 2>&1 &
daemon=$!
for _ in $(seq 100); do [ -S "$sock" ] && break; sleep 0.1; done
[ -S "$sock" ] || { cat "$work/navmapd.log"; fail "the installed navmapd did not start"; }

# 4. A client built against the installed package only, with no source tree in sight.
cp -r "$src/examples/c_client" "$work/example"
cmake -S "$work/example" -B "$work/example-build" -DCMAKE_PREFIX_PATH="$prefix" > "$work/example-configure.log" 2>&1 \
    || { cat "$work/example-configure.log"; fail "configuring the example against the installed package"; }
cmake --build "$work/example-build" > "$work/example-build.log" 2>&1 || { cat "$work/example-build.log"; fail "building the example"; }
if grep -r -q -F -e "$src" -e "$build" "$work/example-build" --include=CMakeCache.txt --include='*.make' --include='*.cmake'; then
    fail "the example's build refers to the source or build tree"
fi
"$work/example-build/navmap-client-example" "$sock" cluster 10 30 > "$work/example.log" 2>&1 \
    || { cat "$work/example.log" "$work/navmapd.log"; fail "the example did not receive 10 frames"; }
grep -E '^frame [0-9]+ 1280x480 stride 5120 pixel ' "$work/example.log" | head -n 3
grep '^frames 10 ' "$work/example.log"
export PKG_CONFIG_PATH="$prefix/$libdir/pkgconfig"
pkg-config --exists --print-errors 'navmap-client >= 0.1' || fail "pkg-config navmap-client"
echo "pkg-config navmap-client: $(pkg-config --cflags --libs navmap-client)"
rpath="-Wl,-rpath,$prefix/$libdir"
# shellcheck disable=SC2046
cc -std=c11 -Wall -Werror -o "$work/example-pc" "$work/example/navmap_client_example.c" $(pkg-config --cflags --libs navmap-client) "$rpath"
"$work/example-pc" "$sock" cluster 3 30 > "$work/example-pc.log" 2>&1 || { cat "$work/example-pc.log"; fail "the pkg-config build"; }
cat > "$work/client.cpp" <<'CPP'
#include <navmap/ipc/client/reconnecting_client.h>
#include <cstdio>
int main(int argc, char** argv) {
    navmap::ipc::ReconnectOptions o;
    o.unix_path = argv[1];
    o.request.profile = *navmap::ipc::defaultStreamProfile("hud");
    navmap::ipc::ReconnectingClient client(o);
    navmap::ipc::ReceivedFrame f;
    for (int i = 0; i < 100; ++i) {
        if (client.next(f, std::chrono::milliseconds(200))) {
            std::printf("C++ client: frame %llu %ux%u\n", static_cast<unsigned long long>(f.header.sequence), f.header.width, f.header.height);
            return argc > 1 ? 0 : 1;
        }
    }
    std::printf("C++ client: no frame: %s\n", client.lastError().c_str());
    return 1;
}
CPP
# shellcheck disable=SC2046
c++ -std=c++17 -Wall -Werror -o "$work/client-cpp" "$work/client.cpp" $(pkg-config --cflags --libs navmap-client) "$rpath"
"$work/client-cpp" "$sock" || fail "the C++ client built with pkg-config"
echo "install tree OK"
