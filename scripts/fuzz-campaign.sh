#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Long fuzzing campaign: runs libFuzzer targets (tests/fuzz) from their checked-in corpora, then
# merges what they found back into tests/fuzz/corpus/<target> minimized (-merge=1
# -use_counters=0: a small set of inputs, smallest first, that reaches every coverage edge the
# corpus and the new finds reach). Prints per target the execs/s and the coverage edges
# (libFuzzer's cov:) at the end. Crash, leak and timeout reproducers are kept in
# <build>/fuzz-campaign/<target>/artifacts/ and make the script exit 1.
#
# usage: scripts/fuzz-campaign.sh [-t seconds] [-j jobs] [-B build dir] [--no-merge | --merge-only] [target...]
#   -t  seconds per target (default 600)
#   -j  parallel fuzzing processes per target (libFuzzer -fork=N; default 1)
#   -B  the clang fuzz build (default build-fuzz; configured and built when missing)
#   --no-merge    fuzz only, leave the corpus as it is
#   --merge-only  no fuzzing: re-minimize the checked-in corpus and report its coverage
#   targets: tile_decode dbc candump control stream_handshake sim_place text_shape (default: all)
# Review the corpus change with `git status tests/fuzz/corpus` and commit it.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds=600
jobs=1
build="$root/build-fuzz"
merge=1
fuzz=1
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    -t) seconds=$2; shift 2 ;;
    -j) jobs=$2; shift 2 ;;
    -B) build=$(realpath -m "$2"); shift 2 ;;
    --no-merge) merge=0; shift ;;
    --merge-only) fuzz=0; shift ;;
    -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
    -*) echo "fuzz-campaign: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
all=(tile_decode dbc candump control stream_handshake sim_place text_shape)
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
for t in "${targets[@]}"; do
  [[ " ${all[*]} " == *" $t "* ]] || { echo "fuzz-campaign: unknown target '$t' (${all[*]})" >&2; exit 2; }
done

if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
      -DNAVMAP_WITH_FUZZ=ON -DNAVMAP_WITH_BENCH=OFF
fi
cmake --build "$build" -j "$(nproc)" --target navmap_fuzz

export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
summary=()
failed=0
for t in "${targets[@]}"; do
  fuzzer="$build/tests/fuzz/${t}_fuzz"
  corpus="$root/tests/fuzz/corpus/$t"
  seeds="$root/tests/fuzz/seeds/$t"
  work="$build/fuzz-campaign/$t"
  rm -rf "$work"
  mkdir -p "$work/new" "$work/artifacts" "$corpus"
  inputs=("$corpus")
  [ -d "$seeds" ] && inputs+=("$seeds")
  before=$(find "$corpus" -type f | wc -l)
  mode=()
  [ "$jobs" -gt 1 ] && mode=(-fork="$jobs")
  rc=0
  if [ "$fuzz" -eq 1 ]; then
    echo "=== $t: $seconds s, $jobs job(s), from $before corpus files"
    # New inputs go to $work/new (the first corpus folder); the repository is only written by the merge.
    (cd "$work" && "$fuzzer" "${mode[@]}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
        -print_final_stats=1 -artifact_prefix="$work/artifacts/" "$work/new" "${inputs[@]}") \
        > "$work/fuzz.log" 2>&1 || rc=$?
  else
    echo "=== $t: merge only, $before corpus files"
    (cd "$work" && "$fuzzer" -runs=0 -timeout=10 -rss_limit_mb=2048 "${inputs[@]}") > "$work/fuzz.log" 2>&1 || rc=$?
  fi
  # The last status line carries the final coverage and rate, e.g. "#123 DONE cov: 812 ft: 2301 ... exec/s: 950".
  last=$(grep -E 'cov: [0-9]+' "$work/fuzz.log" | tail -n 1 || true)
  cov=$(sed -n 's/.*cov: \([0-9]*\).*/\1/p' <<<"$last")
  rate=$(sed -n 's/.*exec\/s:\{0,1\} \([0-9]*\).*/\1/p' <<<"$last")  # fork mode: "exec/s N"
  status=ok
  if [ "$rc" -ne 0 ]; then
    status="FAILED (exit $rc; see $work/fuzz.log, reproducers in $work/artifacts/)"
    failed=1
    tail -n 30 "$work/fuzz.log"
  fi
  after=$before
  if [ "$merge" -eq 1 ]; then
    # Minimize corpus + new finds into a fresh folder that starts with the seeds, so the corpus keeps
    # only what the seeds do not already cover; then replace the checked-in corpus with it.
    merged="$work/merged"
    mkdir -p "$merged"
    [ -d "$seeds" ] && cp "$seeds"/* "$merged"/
    (cd "$work" && "$fuzzer" -merge=1 -use_counters=0 -timeout=10 -rss_limit_mb=2048 "$merged" "$corpus" "$work/new") \
        > "$work/merge.log" 2>&1 || { echo "merge of $t failed: $work/merge.log"; failed=1; continue; }
    [ -d "$seeds" ] && for s in "$seeds"/*; do rm -f "$merged/$(basename "$s")"; done
    find "$corpus" -type f -delete
    cp "$merged"/* "$corpus"/ 2>/dev/null || true
    after=$(find "$corpus" -type f | wc -l)
  fi
  summary+=("$(printf '%-17s %10s %8s %9s %s' "$t" "${rate:-?}" "${cov:-?}" "$before->$after" "$status")")
done

echo
printf '%-17s %10s %8s %9s %s\n' target "exec/s" "cov" corpus status
printf '%s\n' "${summary[@]}"
echo "corpus size: $(du -sh "$root/tests/fuzz/corpus" | cut -f1) ($(find "$root/tests/fuzz/corpus" -type f | wc -l) files)"
exit "$failed"
