#!/usr/bin/env bash
# The unit and gpu tests under AddressSanitizer + UndefinedBehaviorSanitizer, in a build tree of
# their own (build-san/, or $NAVMAP_SAN_BUILD_DIR). Every navmap object, program and library is
# compiled with -fsanitize=address,undefined -fno-omit-frame-pointer; UBSan does not recover, so
# the first report of either sanitizer aborts the test and fails it, and so does a leak at exit.
# The test log is also searched for sanitizer reports, so one from a child process whose exit
# status a test does not look at fails the run too. Leaks inside system libraries are suppressed
# by name in scripts/sanitizers/lsan.supp (each entry says why); nothing of navmap's own is.
# Extra arguments go to the CMake configure step (e.g. the ccache launchers).
#
#   scripts/test-sanitizers.sh                 unit tests, and the gpu tests of NAVMAP_SAN_GPU_TESTS
#   NAVMAP_SAN_GPU_TESTS=all scripts/test-sanitizers.sh    every gpu test
#
# Time: CI has 2 cores and 90 minutes, of which the normal run takes about 17. Under ASan the
# navmap side of every gpu test (meshes, culling, labels, readback, image compares, every malloc)
# runs about twice as slow while llvmpipe's JIT code does not change; all 103 gpu tests take
# about 1060 s of test time uninstrumented on the loaded development VM, which with the ASan
# build from scratch would not fit the ~30 minutes left for this run. So by default it runs the
# unit tests and the gpu tests matched by NAVMAP_SAN_GPU_TESTS below (83 of 103, about half that
# test time) and every pass of the renderer: the GLES renderer and readback, the Andorra map views and
# goldens (terrain, roads GEO and SV, buildings, outlines, glow, aura, labels, text), route
# draping, DEM refinement. Left out: the suites that replay drives frame by frame through the
# same passes (LabelPass, Views/LabelQuality, Cameras/TrajectoryQuality, Paths/TerrainMorphGpu,
# Navmapd/ShippedProfiles). docs/packaging.md "CI" has the figures.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${NAVMAP_SAN_BUILD_DIR:-$root/build-san}"
gpu_tests="${NAVMAP_SAN_GPU_TESTS:-^(GlesRenderer|MapRender(/GrazingRoads)?|AndorraMap|Views/(AndorraGolden|GlowRoadsView|LabelGolden|SvGolden)|Effects/OcclusionGolden|LabelAura|GlowRoads|SvRoads|SvRoadsHighRes|TextLayerTest|RouteDrapeGpu|TerrainMorphRoads|DemRefine|TrajectoryQualityErrors)\\.}"
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"

generator=()
if command -v ninja >/dev/null 2>&1 && [ ! -f "$build/Makefile" ]; then generator=(-G Ninja); fi
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DNAVMAP_WITH_WERROR=ON -DNAVMAP_WITH_TESTS=ON -DNAVMAP_WITH_BENCH=OFF \
  "-DCMAKE_C_FLAGS=$flags" "-DCMAKE_CXX_FLAGS=$flags" \
  "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined" \
  "-DCMAKE_SHARED_LINKER_FLAGS=-fsanitize=address,undefined" \
  "-DCMAKE_MODULE_LINKER_FLAGS=-fsanitize=address,undefined" "$@"
cmake --build "$build" -j "$(nproc)"

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
run -L unit
if [ "$gpu_tests" = all ]; then run -L gpu; else run -L gpu -R "$gpu_tests"; fi

# A report that did not fail its test (a child process, a test that only logs) still fails.
if grep -En 'ERROR: (AddressSanitizer|LeakSanitizer)|runtime error:|SUMMARY: (AddressSanitizer|UndefinedBehaviorSanitizer|LeakSanitizer)' \
     "$log" Testing/Temporary/LastTest*.log >/dev/null 2>&1; then
  echo "test-sanitizers: sanitizer reports in the test output:" >&2
  grep -Eh 'ERROR: (AddressSanitizer|LeakSanitizer)|runtime error:|SUMMARY: ' "$log" Testing/Temporary/LastTest*.log | sort -u >&2
  status=1
fi
exit $status
