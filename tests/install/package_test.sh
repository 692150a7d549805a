#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The Debian packages (CTest `deb_packages`, label install): `cpack -G DEB` in the build tree makes
# navmapd, navmap-view, navmap-wayland, libnavmap-client0 and libnavmap-client-dev (and
# gstreamer1.0-navmap when the build has the GStreamer plugin); their control fields and file lists are
# checked, and they are installed into a throwaway root with dpkg (dpkg --root, maintainer
# scripts chroot-less with DPKG_ROOT: the postinst creates the navmap user there through
# sysusers.d). Without root (dpkg needs it) the packages are unpacked with dpkg -x instead; the
# output says which. The installed daemon then runs from that root.
# Usage: package_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1"
src="$2"
work="$(mktemp -d /tmp/navmap-package-test.XXXXXX)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

(cd "$build" && cpack -G DEB -B "$work/packages") > "$work/cpack.log" 2>&1 || { cat "$work/cpack.log"; fail "cpack -G DEB"; }
version="$(sed -n 's/^#define NAVMAP_VERSION "\(.*\)"/\1/p' "$build/include/navmap/version.h")"
arch="$(dpkg --print-architecture)"
daemon_deb="$work/packages/navmapd_${version}_${arch}.deb"
lib_deb="$work/packages/libnavmap-client0_${version}_${arch}.deb"
dev_deb="$work/packages/libnavmap-client-dev_${version}_${arch}.deb"
view_deb="$work/packages/navmap-view_${version}_${arch}.deb"
# navmap-wayland unless the build left it out (-DNAVMAP_WITH_WAYLAND=OFF): then its checks are skipped.
wayland_deb="$work/packages/navmap-wayland_${version}_${arch}.deb"
debs=("$daemon_deb" "$view_deb" "$lib_deb" "$dev_deb" "$wayland_deb")
if grep -q '^NAVMAP_WITH_WAYLAND:BOOL=OFF$' "$build/CMakeCache.txt"; then
    wayland_deb=""
    debs=("$daemon_deb" "$view_deb" "$lib_deb" "$dev_deb")
fi
for deb in "${debs[@]}"; do
    [ -f "$deb" ] || { ls -l "$work/packages"; fail "missing $(basename "$deb")"; }
done
field() { dpkg-deb -f "$1" "$2"; }
for deb in "${debs[@]}"; do
    echo "== $(basename "$deb") ($(stat -c %s "$deb") bytes)"
    dpkg-deb -I "$deb" | sed -n '/^ Package:/,$p'
    dpkg-deb -c "$deb" | awk '{print "   " $6 ($6 ~ /\/$/ ? "" : "  " $3)}' | grep -v '/$'
done
# Control fields.
[ "$(field "$daemon_deb" Package)" = navmapd ] || fail "daemon package name"
[ "$(field "$lib_deb" Package)" = libnavmap-client0 ] || fail "library package name"
[ "$(field "$dev_deb" Package)" = libnavmap-client-dev ] || fail "-dev package name"
[ "$(field "$view_deb" Package)" = navmap-view ] || fail "viewer package name"
[ -z "$wayland_deb" ] || [ "$(field "$wayland_deb" Package)" = navmap-wayland ] || fail "Wayland client package name"
for deb in "${debs[@]}"; do
    [ "$(field "$deb" Version)" = "$version" ] || fail "$(basename "$deb"): version $(field "$deb" Version)"
    [ "$(field "$deb" Architecture)" = "$arch" ] || fail "$(basename "$deb"): architecture"
done
daemon_depends="$(field "$daemon_deb" Depends)"
lib_depends="$(field "$lib_deb" Depends)"
echo "navmapd Depends: $daemon_depends"
echo "libnavmap-client0 Depends: $lib_depends"
for need in libegl1 libgles2 libsystemd0 libturbojpeg0 libfreetype6 libharfbuzz0b; do
    grep -q "$need" <<< "$daemon_depends" || fail "navmapd does not depend on $need"
done
grep -q openimageio <<< "$daemon_depends" && fail "navmapd depends on OpenImageIO (only image files need it)"
echo "navmap-view Depends: $(field "$view_deb" Depends)"
# Each output is taken whole before it is searched: `producer | grep -q` under pipefail fails
# when grep stops reading early and the producer dies of SIGPIPE.
files() { dpkg-deb -c "$1" | awk '{print $6}'; }
daemon_files="$(files "$daemon_deb")" view_files="$(files "$view_deb")" dev_files="$(files "$dev_deb")"
grep -q openimageio <<< "$(field "$view_deb" Depends)" || fail "navmap-view does not depend on OpenImageIO (its PNG files)"
grep -qx ./usr/bin/navmap-view <<< "$view_files" || fail "navmap-view lacks its program"
grep -q '/navmap-view' <<< "$daemon_files" && fail "navmapd carries navmap-view"
# navmap-wayland: its own package, the only one that needs libwayland-client.
if [ -n "$wayland_deb" ]; then
    echo "navmap-wayland Depends: $(field "$wayland_deb" Depends)"
    grep -q libwayland-client0 <<< "$(field "$wayland_deb" Depends)" || fail "navmap-wayland does not depend on libwayland-client0"
    grep -qx ./usr/bin/navmap-wayland <<< "$(files "$wayland_deb")" || fail "navmap-wayland lacks its program"
fi
grep -q '/navmap-wayland' <<< "$daemon_files" && fail "navmapd carries navmap-wayland"
grep -q wayland <<< "$daemon_depends" && fail "navmapd depends on Wayland"
# The client library needs the C and C++ runtime, nothing of the server.
for d in $(echo "$lib_depends" | tr ',' '\n' | sed 's/(.*//; s/ //g'); do
    case "$d" in libc6|libgcc-s1|libstdc++6) ;; *) fail "libnavmap-client0 depends on $d" ;; esac
done
[ "$(field "$dev_deb" Depends)" = "libnavmap-client0 (= $version)" ] || fail "-dev Depends: $(field "$dev_deb" Depends)"
[ "$(dpkg-deb -f "$lib_deb" Section)" = libs ] || fail "library section"
grep -q '^./conffiles$' <<< "$(dpkg-deb --ctrl-tarfile "$daemon_deb" | tar -t)" || fail "no conffiles"
grep -qx /etc/navmap/navmapd.toml <<< "$(dpkg-deb --ctrl-tarfile "$daemon_deb" | tar -xO ./conffiles)" || fail "conffiles"
grep -q "^libnavmap-client 0 libnavmap-client0" <<< "$(dpkg-deb --ctrl-tarfile "$lib_deb" | tar -xO ./shlibs)" || fail "shlibs"
for f in ./usr/bin/navmapd ./usr/share/navmap/andorra.navmap ./etc/navmap/navmapd.toml \
         ./usr/lib/systemd/system/navmapd.service ./usr/lib/sysusers.d/navmap.conf; do
    grep -qx "$f" <<< "$daemon_files" || fail "navmapd lacks $f"
done
grep -q 'cmake/navmap/navmapConfig.cmake$' <<< "$dev_files" || fail "-dev lacks the CMake package"
grep -q '/include/navmap_client.h$' <<< "$dev_files" || fail "-dev lacks navmap_client.h"

# The GStreamer plugin (NAVMAP_WITH_GSTREAMER): in GStreamer's directory, and it loads from the
# unpacked packages, finding the packaged libnavmap-client relative to itself.
if [ -f "$build/gstreamer-1.0/libgstnavmap.so" ]; then
    gst_deb="$work/packages/gstreamer1.0-navmap_${version}_${arch}.deb"
    [ -f "$gst_deb" ] || { ls -l "$work/packages"; fail "missing $(basename "$gst_deb")"; }
    echo "== $(basename "$gst_deb") ($(stat -c %s "$gst_deb") bytes)"
    dpkg-deb -I "$gst_deb" | sed -n '/^ Package:/,$p'
    grep -q "^libnavmap-client0 (= $version), libgstreamer1.0-0" <<< "$(field "$gst_deb" Depends)" \
        || fail "gstreamer1.0-navmap Depends: $(field "$gst_deb" Depends)"
    plugin_dir="usr/lib/$(dpkg-architecture -qDEB_HOST_MULTIARCH)/gstreamer-1.0"
    grep -qx "./$plugin_dir/libgstnavmap.so" <<< "$(files "$gst_deb")" || fail "gstreamer1.0-navmap: $(files "$gst_deb")"
    if command -v gst-inspect-1.0 > /dev/null; then
        dpkg -x "$gst_deb" "$work/gst-root" && dpkg -x "$lib_deb" "$work/gst-root"
        GST_REGISTRY="$work/gst-registry.bin" GST_PLUGIN_PATH="$work/gst-root/$plugin_dir" \
            gst-inspect-1.0 navmapsrc > "$work/gst-inspect.log" 2>&1 || { cat "$work/gst-inspect.log"; fail "gst-inspect-1.0 navmapsrc"; }
        grep -q "Filename *$work/gst-root/$plugin_dir/libgstnavmap.so" "$work/gst-inspect.log" || fail "navmapsrc from elsewhere"
    fi
fi

# Into a throwaway root.
root="$work/root"
if [ "$(id -u)" -eq 0 ]; then
    echo "== dpkg --root $root (maintainer scripts chroot-less, DPKG_ROOT set)"
    mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates" "$root/etc"
    touch "$root/var/lib/dpkg/status" "$root/var/lib/dpkg/available"
    dpkg --root="$root" --force-depends --force-script-chrootless --log=/dev/null -i "${debs[@]}" \
        > "$work/dpkg.log" 2>&1 || { cat "$work/dpkg.log"; fail "dpkg --root -i"; }
    [ "$(dpkg --root="$root" -l | grep -cE '^ii +(navmapd|navmap-view|navmap-wayland|libnavmap-client0|libnavmap-client-dev) ')" -eq "${#debs[@]}" ] \
        || fail "not installed: $(dpkg --root="$root" -l | grep navmap)"
    if command -v systemd-sysusers >/dev/null; then
        grep -q '^navmap:' "$root/etc/passwd" || fail "the postinst did not create the navmap user"
        echo "postinst: $(grep '^navmap:' "$root/etc/passwd")"
    fi
    dpkg --root="$root" -r libnavmap-client-dev > /dev/null 2>&1 || fail "dpkg -r libnavmap-client-dev"
    [ ! -e "$root/usr/include/navmap_client.h" ] || fail "removing the -dev package left its headers"
    dpkg --root="$root" --force-depends -i "$dev_deb" > /dev/null 2>&1
else
    echo "== not root: dpkg -x into $root (dpkg --root needs root)"
    for deb in "${debs[@]}"; do dpkg -x "$deb" "$root"; done
fi
grep -qx "navmapd $version" <<< "$("$root/usr/bin/navmapd" --version)" || fail "navmapd --version"
grep -q "$version" <<< "$("$root/usr/bin/navmap-view" --version)" \
    || fail "navmap-view --version: $("$root/usr/bin/navmap-view" --version 2>&1)"
[ -z "$wayland_deb" ] || grep -q "$version" <<< "$("$root/usr/bin/navmap-wayland" --version)" \
    || fail "navmap-wayland --version: $("$root/usr/bin/navmap-wayland" --version 2>&1)"
grep -qx "store: $root/usr/share/navmap/andorra.navmap (cache 128 MiB)" <<< "$("$root/usr/bin/navmapd" --check-config)" \
    || fail "the packaged navmapd does not find its store"
grep -qx "ExecStart=/usr/bin/navmapd --config /etc/navmap/navmapd.toml" "$root/usr/lib/systemd/system/navmapd.service" \
    || fail "the packaged unit: $(grep ExecStart "$root/usr/lib/systemd/system/navmapd.service")"
cp -r "$src/examples/c_client" "$work/example"
cmake -S "$work/example" -B "$work/example-build" -DCMAKE_PREFIX_PATH="$root/usr" > "$work/example.log" 2>&1 \
    && cmake --build "$work/example-build" >> "$work/example.log" 2>&1 || { cat "$work/example.log"; fail "example against the -dev package"; }
echo "packages OK"
