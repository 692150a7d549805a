#!/bin/sh
# SPDX-License-Identifier: Apache-2.0
# Real SocketCAN test: boots the Debian kernel (linux-image-amd64) under qemu (TCG, no KVM needed)
# with tests/support/run_in_guest.sh, which loads can, can-raw, can-isotp, can-dev, vcan from the
# host's /lib/modules and shares the host root read-only into the guest over virtio-9p; creates
# vcan0 (CAN FD MTU) there and runs the project's vcan_check, which replays a real Ford log with
# can-utils' canplayer.
#
# usage: run_vcan_test.sh <vcan_check binary> <test data dir> <signal map toml> <navmap.dbc> [<navmap-sim> <store>]
#        <test data dir> is the repository's tests/ipc/data (can/*.candump, dbc/*.dbc).
# exit:  0 pass, 1 fail, 77 skipped (the reason is printed).
# env:   NAVMAP_VCAN_KERNEL (default: newest /boot/vmlinuz-*), NAVMAP_VCAN_TIMEOUT (s, default 90)
set -eu

skip() { echo "SKIPPED: $*"; exit 77; }
fail() { echo "FAIL: $*"; exit 1; }
# Absolute paths: the guest sees the host root at the same paths (chroot /host). A path that
# does not resolve stays as given, so the checks below name it.
abspath() { readlink -f -- "$1" 2>/dev/null || printf '%s\n' "$1"; }

[ "$#" -ge 4 ] || fail "usage: $0 <vcan_check> <test data dir> <signal map toml> <navmap.dbc> [<navmap-sim> <store>]"
CHECK=$(abspath "$1")
DATA=$(abspath "$2")
MAP=$(abspath "$3")
NAVDBC=$(abspath "$4")
LOG="$DATA/can/ford_fusion_2017_lane_keep_assist_on_red_lines.candump"
# Optional: the simulator's SocketCAN output is checked too (navmap-sim --socketcan into vcan0,
# counted with candump) when its binary and a compiled store are given.
SIM=${5:+$(abspath "$5")}
STORE=${6:+$(abspath "$6")}

# The inputs are part of the repository: a missing one is a broken checkout, not an environment
# without qemu, so it fails.
for f in "$LOG" "$DATA/dbc/ford_lincoln_base_pt.dbc" "$DATA/dbc/ford_fusion_2018_pt.dbc" "$MAP" "$NAVDBC"; do
    [ -r "$f" ] || fail "$f: cannot read test input"
done

[ -x /usr/bin/canplayer ] || skip "canplayer not found (apt-get install can-utils)"
[ -x "$CHECK" ] || skip "$CHECK not built"

WORK=$(mktemp -d /tmp/navmap-vcan.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
# What runs in the guest (tests/support/run_in_guest.sh: the host root read-only, /run a tmpfs).
# /tmp stays the host's (read-only): the checkout and build may live there (CI clones).
cat > "$WORK/guest.sh" <<GUEST
ip link add dev vcan0 type vcan && ip link set vcan0 mtu 72 && ip link set vcan0 up \
    || echo "VCAN_SETUP creating vcan0 failed"
"$CHECK" vcan0 "$LOG" /usr/bin/canplayer "$DATA/dbc" "$MAP" "$NAVDBC"
echo "VCAN_EXIT=\$?"
if [ -n "$SIM" ]; then
    /usr/bin/candump -L vcan0 > /run/sim.log &
    sleep 0.5
    "$SIM" --store "$STORE" --dbc "$NAVDBC" --from "Andorra la Vella" --to Encamp --iface vcan0 --socketcan \
        --speed-factor 0 --duration 2 > /run/sim.out 2>&1
    echo "VCAN_SIM_EXIT=\$?"
    sleep 0.5
    kill %1
    echo "VCAN_SIM_FRAMES=\$(grep -c " vcan0 " /run/sim.log) VCAN_SIM_POSITION=\$(grep -c " vcan0 6A0#" /run/sim.log)"
fi
GUEST
OUT=$WORK/console.log
status=0
NAVMAP_GUEST_TIMEOUT=${NAVMAP_VCAN_TIMEOUT:-90} NAVMAP_GUEST_MEMORY=768 NAVMAP_GUEST_ACCEL=${NAVMAP_VCAN_ACCEL:-tcg} \
    "$(dirname "$0")/../../tests/support/run_in_guest.sh" "can can-raw can-isotp can-dev vcan" /bin/sh "$WORK/guest.sh" \
    > "$OUT" 2>&1 || status=$?
[ "$status" -ne 77 ] || { grep "^SKIPPED" "$OUT"; exit 77; }
head -n 1 "$OUT"
grep -E "VCAN_|GUEST_SETUP|failed|Kernel panic" "$OUT" || true
if ! grep -q "VCAN_EXIT=" "$OUT"; then
    echo "--- guest console (tail) ---"; tail -n 40 "$OUT"
    echo "FAIL: the guest did not finish (boot or 9p problem, or timeout)"
    exit 1
fi
if [ -n "$SIM" ]; then
    # 2 s of drive: 20 position frames at 10 Hz, 100 motion frames at 50 Hz, 2 info frames (+ standstill).
    frames=$(sed -n 's/.*VCAN_SIM_FRAMES=\([0-9]*\).*/\1/p' "$OUT" | tail -n 1)
    position=$(sed -n 's/.*VCAN_SIM_POSITION=\([0-9]*\).*/\1/p' "$OUT" | tail -n 1)
    if ! grep -q "VCAN_SIM_EXIT=0" "$OUT" || [ "${frames:-0}" -lt 100 ] || [ "${position:-0}" -lt 20 ]; then
        echo "FAIL: navmap-sim into vcan0: exit $(grep -o 'VCAN_SIM_EXIT=[0-9]*' "$OUT"), ${frames:-0} frames, ${position:-0} NAV_Position"
        exit 1
    fi
    echo "navmap-sim -> vcan0: $frames frames received by candump, $position NAV_Position"
fi
grep -q "VCAN_EXIT=0" "$OUT" && { echo "PASS"; exit 0; }
echo "FAIL"
exit 1
