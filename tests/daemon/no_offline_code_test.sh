#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# navmapd carries no offline code: no function or data defined by the offline libraries (the
# compiler, spill files, sharding, tag interpretation, orthoimage training, synthetic regions)
# is defined in the navmapd executable. Checked on the symbols, so a static link that drags one
# of their objects in fails even when nothing on the link line names the library.
#   no_offline_code_test.sh NM NAVMAPD CONTROL LIBRARY...
# CONTROL is a program that does link the offline code (navmap-compile): the same check must
# find symbols in it, so the test cannot pass by finding nothing anywhere.
set -euo pipefail
nm_tool="$1" navmapd="$2" control="$3"
shift 3
[ "$#" -gt 0 ] || { echo "no_offline_code_test: no libraries given" >&2; exit 2; }

# Strong definitions of functions and data (T, D, B, R); weak ones (inline functions and template
# instantiations such as std::vector<int>) are shared by every program and prove nothing.
strong() { "$nm_tool" --defined-only --demangle "$@" 2>/dev/null | awk '$2 ~ /^[TDBR]$/ { $1 = ""; $2 = ""; sub(/^  /, ""); print }' | sort -u; }

offline="$(mktemp)"
trap 'rm -f "$offline"' EXIT
strong "$@" > "$offline"
count=$(wc -l < "$offline")
[ "$count" -ge 50 ] || { echo "no_offline_code_test: only $count symbols in $* (stripped or wrong files?)" >&2; exit 2; }

found_in() { comm -12 "$offline" <(strong "$1"); }

control_hits=$(found_in "$control" | wc -l)
if [ "$control_hits" -lt 30 ]; then
    echo "no_offline_code_test: the check finds only $control_hits offline symbols in $control, which links them" >&2
    exit 2
fi

hits="$(found_in "$navmapd")"
if [ -n "$hits" ]; then
    echo "navmapd defines $(wc -l <<< "$hits") symbols of the offline libraries:"
    head -n 40 <<< "$hits"
    exit 1
fi
echo "navmapd: none of the $count symbols of the offline libraries ($control holds $control_hits of them)"
