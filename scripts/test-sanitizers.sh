#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The unit and gpu tests under AddressSanitizer + UndefinedBehaviorSanitizer, in a build tree of
# their own (build-san/, or $NAVMAP_SAN_BUILD_DIR). Every navmap object, program and library is
# compiled with -fsanitize=address,undefined -fno-omit-frame-pointer; UBSan does not recover, so
# the first report of either sanitizer aborts the test and fails it, and so does a leak at exit.
# The test log is also searched for sanitizer reports, so one from a child process whose exit
# status a test does not look at fails the run too. Leaks inside system libraries are suppressed
# by name in scripts/sanitizers/lsan.supp (each entry says why); nothing of navmap's own is.
# Extra arguments go to the CMake configure step (e.g. the ccache launchers).
#
#   scripts/test-sanitizers.sh      the named subset below
#   NAVMAP_SAN_TARGETS=all NAVMAP_SAN_GPU_TESTS=all scripts/test-sanitizers.sh    everything
#
# Time: CI has 2 cores and 90 minutes, of which the normal run takes about 17 and the build of
# every target again under ASan would take most of the rest. So by default it builds and runs a named
# subset (NAVMAP_SAN_TARGETS): the unit tests of common, map (rules, geometry with the CGAL
# triangulator, routing, store, guidance), ipc (codecs, DBC, candump, control protocol, net),
# the vehicle state, labels, text and render, and the gpu tests of render_gpu_tests,
# render_case_tests and render_ortho_gpu_tests matched by NAVMAP_SAN_GPU_TESTS: the GLES renderer
# and its readback, the map passes, the render cases (the golden views), the orthoimage generator
# and its worker thread; then render_dmabuf_guest, the renderer's dma-buf export in the vgem guest
# (run_in_guest.sh passes the sanitizers' settings in). Left out: the stream, daemon and sim test
# programs (timing-based rates and whole processes) and the suites that replay drives frame by
# frame. docs/packaging.md "CI".
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${NAVMAP_SAN_BUILD_DIR:-$root/build-san}"
gpu_tests="${NAVMAP_SAN_GPU_TESTS:-^(GlesRenderer|MapRender(/GrazingRoads)?|AndorraMap|Views/GlowRoadsView|Cases/RenderCaseTest|LabelAura|GlowRoads|SvRoads|SvRoadsHighRes|TextLayerTest|RouteDrapeGpu|TerrainMorphRoads|DemRefine|TrajectoryQualityErrors|OrthoGpu|OrthoMap)\\.}"
# A build type of its own (no -O2 -g from RelWithDebInfo); NDEBUG as in the release build. Warnings
# are the normal build's business (-Werror there): GCC warns differently with the sanitizers on.
# -O1 -g1: what the sanitizers' documentation recommends, and quicker to build on CI's two cores
# than RelWithDebInfo's -O2 -g.
flags="-O1 -g1 -DNDEBUG -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"

# The default store is made by the normal build's navmap-compile where there is one (the same
# bytes, docs/packaging.md), not by an instrumented one.
host_tools=()
if [ -f "$root/build/NavmapHostTools.cmake" ]; then host_tools=("-DNAVMAP_HOST_TOOLS=$root/build/NavmapHostTools.cmake"); fi
generator=()
if command -v ninja >/dev/null 2>&1 && [ ! -f "$build/Makefile" ]; then generator=(-G Ninja); fi
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Sanitize \
  -DNAVMAP_WITH_WERROR=OFF -DNAVMAP_WITH_TESTS=ON -DNAVMAP_WITH_BENCH=OFF "${host_tools[@]}" \
  "-DCMAKE_C_FLAGS=$flags" "-DCMAKE_CXX_FLAGS=$flags" \
  "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined" \
  "-DCMAKE_SHARED_LINKER_FLAGS=-fsanitize=address,undefined" \
  "-DCMAKE_MODULE_LINKER_FLAGS=-fsanitize=address,undefined" "$@"
# The test programs of the named subset (NAVMAP_SAN_TARGETS; "all": every target), and what they link.
targets="${NAVMAP_SAN_TARGETS:-common_check_test map_rules_test map_geometry_test map_routing_test map_store_test map_spill_test map_compile_stages_test map_guidance_test ipc_unit_tests ipc_net_tests ipc_control_tests vehicle_state_tests navmap_labels_test navmap_text_test render_unit_tests render_lod_unit_tests render_gpu_tests render_ortho_gpu_tests render_case_unit_tests render_case_tests}"
if [ "$targets" = all ]; then
  cmake --build "$build" -j "$(nproc)"
else
  # shellcheck disable=SC2086
  cmake --build "$build" -j "$(nproc)" --target navmap_default_store $targets
fi

supp="$root/scripts/sanitizers"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp"

status=0
cd "$build"
log="$build/sanitizer-tests.log"
: >"$log"
run() {
  echo "test-sanitizers: ctest $*" | tee -a "$log"
  ctest --output-on-failure --timeout 1800 -j "$(nproc)" "$@" 2>&1 | tee -a "$log" || status=1
}
# Tests that bound the process's resident memory measure nothing under ASan (its quarantine
# keeps freed blocks, its shadow memory grows with the heap): left out, and said so.
rss_bound='BoundedMemory|NoFdOrMemoryGrowth|RingMemoryHasACeiling|NeitherLockOutTheClusterNorGrowMemory'
echo "test-sanitizers: leaving out the resident-memory bounds (${rss_bound}): ASan's quarantine and shadow memory grow RSS" | tee -a "$log"
run -L unit -E "$rss_bound"
if [ "$gpu_tests" = all ]; then run -L gpu; else run -L gpu -R "$gpu_tests"; fi
# The dma-buf export on real kernel dma-bufs, in the vgem guest (docs/gles-profile.md "dma-buf
# export"; skipped, with the reason, where qemu or the kernel is missing).
run -R '^render_dmabuf_guest$'

# A report that did not fail its test (a child process, a test that only logs) still fails.
if grep -En 'ERROR: (AddressSanitizer|LeakSanitizer)|runtime error:|SUMMARY: (AddressSanitizer|UndefinedBehaviorSanitizer|LeakSanitizer)' \
     "$log" Testing/Temporary/LastTest*.log >/dev/null 2>&1; then
  echo "test-sanitizers: sanitizer reports in the test output:" >&2
  grep -Eh 'ERROR: (AddressSanitizer|LeakSanitizer)|runtime error:|SUMMARY: ' "$log" Testing/Temporary/LastTest*.log | sort -u >&2
  status=1
fi
exit $status
