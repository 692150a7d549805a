#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# One benchmark command (docs/benchmarks/README.md). Runs every benchmark program of a build
# (Google Benchmark JSON), the label quality replay of the reference drive and navmapd's own
# frame breakdown (the latency benchmark with get_status "passes" per profile), and writes one JSON with the
# machine, the commit, the date and the load average before and after each program.
#   scripts/bench.sh                       all of it, into bench-<commit>.json (or --out FILE)
#   scripts/bench.sh --only 'labels|route' programs whose name matches (grep -E)
#   scripts/bench.sh --compare REV         builds REV in a git worktree (~/.cache/navmap/bench/<rev>,
#                                          or under $NAVMAP_BENCH_DIR) and
#                                          runs both builds' programs interleaved, A (REV) then B (this
#                                          tree) then B then A ..., for --rounds N (default 3); prints
#                                          B/A per figure with its spread over the rounds and flags
#                                          every figure worse by more than the spread (exit 3)
#   --args 'ARGS'                          extra arguments for every Google Benchmark program
#                                          (e.g. --args --benchmark_min_time=0.2)
# NAVMAP_BUILD_DIR names the build of this tree (default build/, built with benchmarks first).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${NAVMAP_BUILD_DIR:-$root/build}"
only=""
out=""
compare=""
rounds=3
extra=""
while [ $# -gt 0 ]; do
    case "$1" in
        --only) only="$2"; shift 2 ;;
        --out) out="$2"; shift 2 ;;
        --compare) compare="$2"; shift 2 ;;
        --rounds) rounds="$2"; shift 2 ;;
        --args) extra="$2"; shift 2 ;;
        -h|--help) sed -n '3,17p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "bench.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
done
case "$build" in /*) ;; *) build="$PWD/$build" ;; esac
case "$rounds" in ''|*[!0-9]*) echo "bench.sh: --rounds wants a number, got '$rounds'" >&2; exit 2 ;; esac

# name|path in a build|arguments. Every program prints Google Benchmark JSON on stdout.
programs=(
    "labels|bench/labels/navmap_labels_bench|"
    "label_pass|render/tools/label_quality/navmap_label_pass_bench|"
    "text|bench/text/navmap_text_bench|"
    "map|bench/map/map_bench|"
    "ipc|bench/ipc/ipc_bench|"
    "sim|bench/sim/sim_bench|"
    "vehicle|bench/vehicle/vehicle_bench|"
    "stream|bench/stream/stream_bench|"
    "frame|bench/navmap-bench|"
    "occlusion|bench/navmap_occlusion_bench|"
    "road_technique|bench/navmap_road_technique_bench|"
    "ortho|bench/navmap_ortho_bench|"
    "route|bench/navmap_route_bench|"
    "daemon_frame|bench/stream/navmap_latency_bench|"
    "boot|bench/daemon/navmap_boot_bench|"
)
# The label quality of the reference drive (docs/labels.md), as a figure set of its own.
label_replay="render/tools/label_quality/navmap-label-quality"

selected=()
for p in "${programs[@]}" "label_replay|$label_replay|"; do
    name="${p%%|*}"
    if [ -z "$only" ] || grep -Eq "$only" <<<"$name"; then selected+=("$p"); fi
done
[ ${#selected[@]} -gt 0 ] || { echo "bench.sh: --only '$only' matches no program" >&2; exit 2; }
targets=()  # the CMake targets behind them (the daemon benchmarks exec navmapd)
for p in "${selected[@]}"; do
    rest="${p#*|}"
    path="${rest%%|*}"
    targets+=("$(basename "$path")")
    case "${p%%|*}" in daemon_frame|boot) targets+=(navmapd) ;; esac
done

build_tree() {  # build_tree SRC BUILD: configure (benchmarks on) and build the selected programs
    local src="$1" dir="$2"
    mkdir -p "$dir"
    local generator=()
    if command -v ninja >/dev/null 2>&1 && [ ! -f "$dir/Makefile" ]; then generator=(-G Ninja); fi
    local launcher=()
    if command -v ccache >/dev/null 2>&1; then
        launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    fi
    cmake -S "$src" -B "$dir" "${generator[@]}" "${launcher[@]}" -DNAVMAP_WITH_TESTS=ON -DNAVMAP_WITH_BENCH=ON \
        >"$dir/bench-configure.log" 2>&1 || { cat "$dir/bench-configure.log" >&2; return 1; }
    cmake --build "$dir" -j "$(nproc)" --target "${targets[@]}" >"$dir/bench-build.log" 2>&1 ||
        { tail -40 "$dir/bench-build.log" >&2; return 1; }
}

run_one() {  # run_one BUILD SPEC OUTFILE: one program, its JSON into OUTFILE, its log beside it
    local dir="$1" spec="$2" file="$3"
    local name="${spec%%|*}" rest="${spec#*|}"
    local path="${rest%%|*}"
    local exe="$dir/$path"
    if [ ! -x "$exe" ]; then
        echo "{\"error\": \"not built: $path\"}" >"$file"
        echo "bench.sh: $name: $exe is not built" >&2
        return 0
    fi
    local start=$SECONDS
    local rc=0
    if [ "$name" = label_replay ]; then
        (cd "$dir" && "$exe" --trajectory "$root/data/drives/andorra-urban-trajectory.json" \
            --camera zoom=16,pitch=60 --frames 300 --no-occlusion) >"$file" 2>"$file.log" || rc=$?
    else
        # shellcheck disable=SC2086
        (cd "$dir" && "$exe" --benchmark_format=json $extra) >"$file" 2>"$file.log" || rc=$?
    fi
    echo "bench.sh: $name: $((SECONDS - start)) s (rc $rc, $dir)" >&2
    [ $rc -eq 0 ] || { echo "{\"error\": \"exit status $rc\"}" >"$file"; tail -5 "$file.log" >&2; }
}

work="$(mktemp -d "${TMPDIR:-/tmp}/navmap-bench.XXXXXX")"
trap 'rm -rf "$work"' EXIT
commit="$(git -C "$root" rev-parse --short HEAD)"
[ -z "$(git -C "$root" status --porcelain --untracked-files=no)" ] || commit="$commit+dirty"

if [ -z "$compare" ]; then
    [ -d "$build" ] || { echo "bench.sh: no build in $build (scripts/build.sh -DNAVMAP_WITH_BENCH=ON)" >&2; exit 2; }
    for spec in "${selected[@]}"; do
        name="${spec%%|*}"
        loadavg="$(cut -d' ' -f1-3 /proc/loadavg)"
        run_one "$build" "$spec" "$work/$name.json"
        echo "$name $loadavg $(cut -d' ' -f1-3 /proc/loadavg)" >>"$work/load.txt"
    done
    out="${out:-$root/bench-$commit.json}"
    python3 "$root/scripts/bench_report.py" merge --commit "$commit" --out "$out" --load "$work/load.txt" \
        "$work"/*.json
    echo "bench.sh: wrote $out"
    exit 0
fi

# A/B: A = REV, B = this tree, interleaved in one window.
rev="$(git -C "$root" rev-parse --short "$compare^{commit}")" ||
    { echo "bench.sh: --compare: '$compare' is not a commit" >&2; exit 2; }
# The worktree keeps this tree's layout (sources, build/ inside), so a compiler cache that maps
# paths relative to the build folder serves the files REV shares with this tree.
base="${NAVMAP_BENCH_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/navmap/bench}/$rev"
mkdir -p "$(dirname "$base")"
if [ ! -e "$base/.git" ]; then
    git -C "$root" worktree add --detach "$base" "$rev" >/dev/null
fi
echo "bench.sh: building A = $rev in $base/build" >&2
build_tree "$base" "$base/build"
echo "bench.sh: building B = $commit in $build" >&2
build_tree "$root" "$build"
for ((r = 1; r <= rounds; ++r)); do
    for spec in "${selected[@]}"; do
        name="${spec%%|*}"
        if [ $((r % 2)) -eq 1 ]; then
            run_one "$base/build" "$spec" "$work/A-$r-$name.json"
            run_one "$build" "$spec" "$work/B-$r-$name.json"
        else
            run_one "$build" "$spec" "$work/B-$r-$name.json"
            run_one "$base/build" "$spec" "$work/A-$r-$name.json"
        fi
    done
done
out="${out:-$root/bench-compare-$rev-$commit.json}"
rc=0
python3 "$root/scripts/bench_report.py" compare --a "$rev" --b "$commit" --rounds "$rounds" --out "$out" \
    --dir "$work" || rc=$?
echo "bench.sh: wrote $out"
exit $rc
