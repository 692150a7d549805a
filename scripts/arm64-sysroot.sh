#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Makes (or reuses) an arm64 sysroot of Debian packages for the aarch64 cross build of navmapd
# (scripts/cross-build.sh --daemon) and for running it under qemu-aarch64-static -L <sysroot>.
# Nothing is installed on the build machine beyond the arm64 architecture in apt's list: the
# packages' dependency closure is resolved by apt as if nothing were installed (an empty dpkg
# status, arm64 as the native architecture), fetched with `apt-get download` and unpacked with
# `dpkg -x` into a folder of their own (docs/packaging.md "Cross-compiling for aarch64").
#   arm64-sysroot.sh        prints the sysroot's path on its last line, NAVMAP_SYSROOT=<path>
# The folder is ${NAVMAP_SYSROOT_CACHE:-${XDG_CACHE_HOME:-~/.cache}/navmap}/arm64-sysroot-<key>,
# where <key> is a hash of the resolved package list (names and versions): a run with the same
# list reuses it, a changed list (another package, a security update) makes a new one.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
# The daemon's build list of scripts/install-deps.sh (its toolchain and tool packages aside),
# the test and benchmark libraries, the C and C++ runtime's development files (the cross
# compiler's are found relative to the sysroot), and Mesa's arm64 drivers to run the gpu tests.
mapfile -t PACKAGES < <("$root/scripts/install-deps.sh" --list-arm64)
cache="${NAVMAP_SYSROOT_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/navmap}"
mkdir -p "$cache"

SUDO=()
if [ "$(id -u)" -ne 0 ] && command -v sudo >/dev/null 2>&1; then SUDO=(sudo); fi
if ! dpkg --print-foreign-architectures | grep -qx arm64; then
    echo "arm64-sysroot: adding the arm64 architecture to dpkg/apt (nothing is installed)" >&2
    "${SUDO[@]}" dpkg --add-architecture arm64
    "${SUDO[@]}" apt-get update -q >&2
fi

# The closure as apt would install it into an empty arm64 system (no recommends).
empty="$(mktemp)"
trap 'rm -f "$empty"' EXIT
resolve() {
    apt-get -s -o Dir::State::status="$empty" -o APT::Architecture=arm64 \
        -o APT::Architectures::=arm64 -o APT::Architectures::=all \
        install --no-install-recommends "${PACKAGES[@]}"
}
if ! sim="$(resolve 2>&1)"; then
    "${SUDO[@]}" apt-get update -q >&2   # no arm64 lists yet
    sim="$(resolve)"
fi
# "Inst name (version Suite [arch])" -> name:arch=version
list="$(sed -n 's/^Inst \([^ ]*\) (\([^ ]*\) .*\[\([a-z0-9]\+\)\].*/\1:\3=\2/p' <<<"$sim" | sort)"
count="$(wc -l <<<"$list")"
[ "$count" -gt 0 ] || { echo "arm64-sysroot: apt resolved no packages:" >&2; echo "$sim" >&2; exit 1; }
key="$(sha256sum <<<"$list" | cut -c1-16)"
sysroot="$cache/arm64-sysroot-$key"
if [ -f "$sysroot/.navmap-sysroot-complete" ]; then
    echo "arm64-sysroot: reusing $sysroot ($count packages)" >&2
    echo "NAVMAP_SYSROOT=$sysroot"
    exit 0
fi

start=$SECONDS
rm -rf "$sysroot" "$sysroot.debs"
mkdir -p "$sysroot.debs"
echo "arm64-sysroot: downloading $count arm64 packages into $sysroot.debs" >&2
# apt-get download drops privileges to the _apt user, who cannot write under a home folder: not here.
(cd "$sysroot.debs" && xargs apt-get download -q -o APT::Sandbox::User=root <<<"$list" >&2)
fetched=$SECONDS
echo "arm64-sysroot: $(find "$sysroot.debs" -name '*.deb' | wc -l) packages," \
     "$(du -sh "$sysroot.debs" | cut -f1) in $((fetched - start)) s; unpacking" >&2
mkdir -p "$sysroot"
for deb in "$sysroot.debs"/*.deb; do dpkg -x "$deb" "$sysroot"; done

# Debian 12's merged /usr (the usrmerge layout of an installed system): packages still ship files
# in /lib, /lib64, /bin and /sbin, which an installed system reaches through links to usr/.
for d in lib lib64 bin sbin; do
    [ "$d" != lib64 ] || [ -e "$sysroot/lib64" ] || continue   # aarch64's loader is in lib
    if [ -d "$sysroot/$d" ] && [ ! -L "$sysroot/$d" ]; then
        mkdir -p "$sysroot/usr/$d"
        cp -a "$sysroot/$d/." "$sysroot/usr/$d/"
        rm -rf "${sysroot:?}/$d"
    fi
    ln -sfn "usr/$d" "$sysroot/$d"
done
# Absolute links (libz.so -> /lib/aarch64-linux-gnu/libz.so.1.2.13) would point into the build
# machine: make each relative to its own folder, inside the sysroot.
while IFS= read -r -d '' link; do
    target="$(readlink "$link")"
    case "$target" in
        /*) ln -sfn "$(realpath -m --relative-to="$(dirname "$link")" "$sysroot$target")" "$link" ;;
    esac
done < <(find "$sysroot" -type l -print0)
# Links that maintainer scripts would make (dpkg -x runs none): update-alternatives' choice of the
# reference BLAS and LAPACK (libblas.so.3 -> blas/libblas.so.3), which OpenCV, Armadillo and ARPACK
# (OpenImageIO's dependencies) link to.
multiarch="$sysroot/usr/lib/aarch64-linux-gnu"
for alt in blas lapack; do
    for f in "$multiarch/$alt"/lib*.so*; do
        if [ -e "$f" ] && [ ! -e "$multiarch/$(basename "$f")" ]; then
            ln -s "$alt/$(basename "$f")" "$multiarch/$(basename "$f")"
        fi
    done
done
# CMake package files naming absolute library paths of the target (libjpeg-turbo's
# IMPORTED_LOCATION "/usr/lib/aarch64-linux-gnu/libturbojpeg.so...") are given the sysroot's (the
# linker reads such paths as the build machine's). Not the "/usr move" check of
# configure_package_config_file (_realOrig): it compares against the package's original folder.
grep -rlZ --include='*.cmake' -e '[ ;"]/usr/lib/aarch64-linux-gnu/' "$sysroot/usr/lib" 2>/dev/null |
    xargs -0 -r sed -i -E "/_realOrig/! s#([ ;\"])/usr/lib/aarch64-linux-gnu/#\1$sysroot/usr/lib/aarch64-linux-gnu/#g"
if [ ! -e "$sysroot/lib/ld-linux-aarch64.so.1" ] || [ -n "$(find "$sysroot/usr/lib" -maxdepth 1 -name '*x86_64*' -print -quit)" ]; then
    echo "arm64-sysroot: $sysroot is not an arm64 system (no lib/ld-linux-aarch64.so.1, or amd64 files)" >&2
    exit 1
fi
rm -rf "$sysroot.debs"
printf '%s\n' "$list" >"$sysroot/.navmap-sysroot-packages"
touch "$sysroot/.navmap-sysroot-complete"
echo "arm64-sysroot: $sysroot: $count packages, $(du -sh "$sysroot" | cut -f1);" \
     "download $((fetched - start)) s, unpack $((SECONDS - fetched)) s" >&2
echo "NAVMAP_SYSROOT=$sysroot"
