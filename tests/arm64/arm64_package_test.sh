#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The arm64 Debian packages (CTest `arm64_packages`, label arm64): `cpack -G DEB` in the aarch64
# cross tree makes navmapd, navmap-view, libnavmap-client0 and libnavmap-client-dev for arm64; they
# are unpacked into a throwaway root (dpkg -x: nothing of it is installed on this machine), and the
# packaged navmapd runs there under qemu-aarch64-static with the arm64 sysroot's libraries
# (<cross>/arm64-run): --version, and --check-config finding the packaged store and configuration.
# Usage: arm64_package_test.sh CROSS_BUILD_DIR
set -euo pipefail
build="$1"
work="$(mktemp -d /tmp/navmap-arm64-package-test.XXXXXX)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

(cd "$build" && cpack -G DEB -B "$work/packages") > "$work/cpack.log" 2>&1 || { cat "$work/cpack.log"; fail "cpack -G DEB"; }
version="$(sed -n 's/^#define NAVMAP_VERSION "\(.*\)"/\1/p' "$build/include/navmap/version.h")"
root="$work/root"
for p in navmapd navmap-view libnavmap-client0 libnavmap-client-dev; do
    deb="$work/packages/${p}_${version}_arm64.deb"
    [ -f "$deb" ] || { ls -l "$work/packages"; fail "missing $(basename "$deb")"; }
    [ "$(dpkg-deb -f "$deb" Architecture)" = arm64 ] || fail "$(basename "$deb"): architecture $(dpkg-deb -f "$deb" Architecture)"
    echo "$(basename "$deb"): $(stat -c %s "$deb") bytes"
    dpkg -x "$deb" "$root"
done
for f in usr/bin/navmapd usr/bin/navmap-view usr/bin/navmap-ctl usr/bin/navmap-compile; do
    machine="$(readelf -h "$root/$f" | sed -n 's/^ *Machine: *//p')"
    [ "$machine" = AArch64 ] || fail "$f is $machine"
done
lib="$(find "$root/usr/lib" -name 'libnavmap-client.so.0.*' -type f)"
[ "$(readelf -h "$lib" | sed -n 's/^ *Machine: *//p')" = AArch64 ] || fail "$lib is not AArch64"
[ -f "$root/usr/share/navmap/andorra.navmap" ] || fail "navmapd lacks the default store"
[ -f "$root/etc/navmap/navmapd.toml" ] || fail "navmapd lacks its configuration"

run="$build/arm64-run"
out="$("$run" "$root/usr/bin/navmapd" --version 2>&1)" || fail "navmapd --version under qemu: $out"
echo "navmapd --version (arm64, qemu): $out"
grep -qx "navmapd $version" <<< "$out" || fail "navmapd --version: $out"
# As the amd64 package test checks it: the defaults, with the store found beside the program.
out="$("$run" "$root/usr/bin/navmapd" --check-config 2>&1)" || fail "navmapd --check-config under qemu: $out"
echo "  ${out//$'\n'/$'\n'  }"
grep -qx "store: $root/usr/share/navmap/andorra.navmap (cache 128 MiB)" <<< "$out" \
    || fail "the packaged arm64 navmapd does not find its store"
# The packaged configuration file.
out="$("$run" "$root/usr/bin/navmapd" --check-config --config "$root/etc/navmap/navmapd.toml" 2>&1)" \
    || fail "navmapd --check-config --config <packaged navmapd.toml> under qemu: $out"
grep -q cluster <<< "$out" || fail "--check-config does not print the cluster profile: $out"
out="$("$run" "$root/usr/bin/navmap-view" --version 2>&1)" || fail "navmap-view --version under qemu: $out"
grep -q "$version" <<< "$out" || fail "navmap-view --version: $out"
echo "arm64 packages OK"
