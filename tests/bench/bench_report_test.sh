#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# scripts/bench_report.py on made-up benchmark JSON: the merge keeps the commit, the machine
# and every figure; the comparison flags a figure worse by more than its spread (exit 3), calls
# a faster one better, leaves noise alone, and reads fps the other way round.
set -euo pipefail
report="$1/scripts/bench_report.py"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
gbench() {  # gbench FILE FRAME_NS NOISY_NS FPS WORK
    cat >"$1" <<JSON
{"context": {"num_cpus": 2, "mhz_per_cpu": 2000, "library_build_type": "release"},
 "benchmarks": [
  {"name": "BM_Frame/2000", "run_type": "iteration", "iterations": 10, "real_time": $2, "cpu_time": $2, "time_unit": "ns", "sat_tests": $5},
  {"name": "BM_Noisy", "run_type": "iteration", "iterations": 10, "real_time": $3, "cpu_time": $3, "time_unit": "ns"},
  {"name": "BM_Fps", "run_type": "iteration", "iterations": 1, "real_time": 1, "cpu_time": 1, "time_unit": "ms", "fps": $4},
  {"name": "BM_Broken", "error_occurred": true, "error_message": "no GPU"}]}
JSON
}
gbench "$work/labels.json" 1000 500 60 300
echo '{"drawn": {"pops_per_min": 4.5, "label_count": 12}}' >"$work/label_replay.json"
echo "labels 0.50 0.40 0.30 0.60 0.45 0.31" >"$work/load.txt"
python3 "$report" merge --commit abc1234 --out "$work/merged.json" --load "$work/load.txt" \
    "$work/labels.json" "$work/label_replay.json" >"$work/merge.out"
python3 - "$work/merged.json" <<'PY' || fail "merged JSON"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["commit"] == "abc1234", d["commit"]
assert d["machine"]["cpus"] >= 1 and d["machine"]["num_cpus"] == 2
f = d["programs"]["labels"]["figures"]
assert f["labels:BM_Frame/2000:real_time_ns"] == 1000 and f["labels:BM_Frame/2000:sat_tests"] == 300, f
assert not any("Broken" in k for k in f), "a failed benchmark has no figures"
assert d["programs"]["labels"]["load_average"]["before"] == [0.5, 0.4, 0.3]
assert d["programs"]["label_replay"]["figures"]["label_replay::drawn.pops_per_min"] == 4.5
PY
# Three rounds: BM_Frame 30 % slower with 1 % noise, BM_Noisy +-25 % either way, fps 20 % lower,
# the work counter halved.
for r in 1 2 3; do
    gbench "$work/A-$r-labels.json" $((1000 + r * 5)) $((500 + (r - 2) * 120)) 60 300
    gbench "$work/B-$r-labels.json" $((1300 + r * 4)) $((500 - (r - 2) * 120)) 48 150
done
rc=0
python3 "$report" compare --a old --b new --rounds 3 --out "$work/cmp.json" --dir "$work" >"$work/cmp.out" || rc=$?
cat "$work/cmp.out"
[ $rc -eq 3 ] || fail "a worse figure must exit with 3, got $rc"
grep -Eq '^labels:BM_Frame/2000:real_time_ns +1010 +1308 +1\.29[0-9] .* worse$' "$work/cmp.out" || fail "BM_Frame not flagged"
grep -Eq '^labels:BM_Frame/2000:sat_tests .* 0\.500 .* better$' "$work/cmp.out" || fail "halved work not better"
grep -Eq '^labels:BM_Noisy:real_time_ns .* same$' "$work/cmp.out" || fail "noise flagged"
grep -Eq '^labels:BM_Fps:fps .* 0\.800 .* worse$' "$work/cmp.out" || fail "lower fps not worse"
grep -q '2 worse: ' "$work/cmp.out" || fail "summary line"
# Same builds: nothing flagged, exit 0.
for r in 1 2 3; do cp "$work/A-$r-labels.json" "$work/B-$r-labels.json"; done
python3 "$report" compare --a old --b old --rounds 3 --out "$work/same.json" --dir "$work" >"$work/same.out" ||
    fail "identical runs flagged: $(cat "$work/same.out")"
grep -q ' 0 worse' "$work/same.out" || fail "identical runs: $(tail -1 "$work/same.out")"
echo "bench_report: merge and compare OK"
