#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The default store made by an imported host navmap-compile (CTest `host_tools_store`, label
# install), the path a cross build takes (map/compile/CMakeLists.txt): a second build tree configured
# with NAVMAP_HOST_TOOLS=<this build>/NavmapHostTools.cmake builds the store target without
# compiling a navmap-compile of its own, and the store it makes is byte for byte the one this
# build made.
# Usage: host_tools_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1"
src="$2"
work="$(mktemp -d /tmp/navmap-host-tools-test.XXXXXX)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

tools="$build/NavmapHostTools.cmake"
[ -f "$tools" ] || fail "$tools missing: the native build exports navmap-compile there"
[ -f "$build/andorra.navmap" ] || fail "$build/andorra.navmap missing: build navmap_default_store first"
generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
cmake -S "$src" -B "$work/b" "${generator[@]}" -DNAVMAP_HOST_TOOLS="$tools" -DNAVMAP_WITH_TESTS=OFF \
      -DNAVMAP_WITH_BENCH=OFF > "$work/configure.log" 2>&1 \
    || { cat "$work/configure.log"; fail "configure with NAVMAP_HOST_TOOLS"; }
cmake --build "$work/b" --target navmap_default_store > "$work/build.log" 2>&1 \
    || { cat "$work/build.log"; fail "building navmap_default_store with the imported compiler"; }
grep -q "$build/map/navmap-compile" "$work/build.log" || grep -rq "$build/map/navmap-compile" "$work/b/build.ninja" "$work/b/Makefile" 2>/dev/null \
    || fail "the store rule does not run $build/map/navmap-compile"
if find "$work/b" -name navmap-compile -type f | grep -q .; then
    fail "the second tree compiled its own navmap-compile: $(find "$work/b" -name navmap-compile -type f)"
fi
cmp "$work/b/andorra.navmap" "$build/andorra.navmap" \
    || fail "the store made by the imported compiler differs from $build/andorra.navmap"
echo "host_tools_store: $work/b/andorra.navmap made by $build/map/navmap-compile, $(stat -c %s "$work/b/andorra.navmap") bytes, identical"
