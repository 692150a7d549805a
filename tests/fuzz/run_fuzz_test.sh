#!/bin/sh
# SPDX-License-Identifier: Apache-2.0
# CTest label `fuzz`: runs one libFuzzer target for a fixed time, starting from its checked-in
# corpus. New inputs go to a scratch folder in the build tree, never into the repository
# (scripts/fuzz-campaign.sh is the way to grow the corpora). libFuzzer exits non-zero on a crash,
# a sanitizer report, a leak, an input slower than 10 s or more than 2 GB RSS; the reproducer is
# left in <scratch>/artifacts/ and named in the output.
#
# usage: run_fuzz_test.sh <fuzzer binary> <corpus dir> <scratch dir> <seconds>
set -eu
[ "$#" -eq 4 ] || { echo "usage: $0 <fuzzer> <corpus dir> <scratch dir> <seconds>"; exit 2; }
fuzzer=$1 corpus=$2 scratch=$3 seconds=$4
n=$(find "$corpus" -type f 2>/dev/null | wc -l)
[ "$n" -gt 0 ] || { echo "FAIL: $corpus: no corpus files"; exit 1; }
rm -rf "$scratch"
mkdir -p "$scratch/new" "$scratch/artifacts"
echo "$(basename "$fuzzer"): $seconds s from $n corpus files in $corpus"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
exec "$fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$scratch/artifacts/" "$scratch/new" "$corpus"
