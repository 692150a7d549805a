#!/bin/sh
# SPDX-License-Identifier: Apache-2.0
# Regenerates the drives shipped in data/drives (see data/drives/README.md).
# Usage: sim/tools/make_drives.sh [build-dir]   (needs <build-dir>/sim/navmap-sim and andorra.navmap)
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build}
sim="$build/sim/navmap-sim"
out="$root/data/drives"
common="-q --store $build/andorra.navmap"
$sim $common --from "Andorra la Vella" --to "Encamp" --noise-m 1.5 --seed 1 \
    --out "$out/andorra_la_vella-encamp.candump" --route-out "$out/andorra_la_vella-encamp.route.json"
$sim $common --from "les Escaldes" --to "Ordino" --noise-m 1.5 --seed 2 \
    --out "$out/escaldes-ordino.candump" --route-out "$out/escaldes-ordino.route.json"
$sim $common --from "Andorra la Vella" --to "les Escaldes" --noise-m 2.5 --dropouts 2 --dropout-s 4 \
    --bad-frames 4 --burst-size 5 --seed 3 \
    --out "$out/short-faults.candump" --route-out "$out/short-faults.route.json"
