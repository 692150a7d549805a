#!/bin/sh
# SPDX-License-Identifier: Apache-2.0
# Real SocketCAN test: boots the Debian kernel (linux-image-amd64) under qemu (TCG, no KVM needed),
# loads can, can-raw, can-isotp, can-dev, vcan from the host's /lib/modules, shares the host root
# read-only into the guest over virtio-9p, creates vcan0 (CAN FD MTU) and runs the project's
# vcan_check there, which replays a real Ford log with can-utils' canplayer.
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

QEMU=$(command -v qemu-system-x86_64 || true)
[ -n "$QEMU" ] || skip "qemu-system-x86_64 not found (apt-get install qemu-system-x86)"
KERNEL=${NAVMAP_VCAN_KERNEL:-$(ls -1 /boot/vmlinuz-* 2>/dev/null | sort -V | tail -n 1)}
[ -n "$KERNEL" ] && [ -r "$KERNEL" ] || skip "no readable /boot/vmlinuz-* (apt-get install linux-image-amd64)"
KVER=${KERNEL#*/vmlinuz-}
MODDIR=/lib/modules/$KVER
[ -r "$MODDIR/modules.dep" ] || skip "$MODDIR/modules.dep missing for kernel $KVER"
BUSYBOX=$(command -v busybox || true)
[ -n "$BUSYBOX" ] || skip "busybox not found (apt-get install busybox-static)"
file -L "$BUSYBOX" 2>/dev/null | grep -q "statically linked" || [ -x /bin/busybox ] || skip "busybox is not static"
[ -x /usr/bin/canplayer ] || skip "canplayer not found (apt-get install can-utils)"
command -v cpio >/dev/null || skip "cpio not found"
[ -x "$CHECK" ] || skip "$CHECK not built"

WORK=$(mktemp -d /tmp/navmap-vcan.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
ROOT=$WORK/root
mkdir -p "$ROOT/bin" "$ROOT/proc" "$ROOT/sys" "$ROOT/dev" "$ROOT/host" "$ROOT/modules"
cp "$BUSYBOX" "$ROOT/bin/busybox"

# Modules in dependency order (modules.dep lists the dependencies of each module).
ORDER=$WORK/order
: > "$ORDER"
add_module() {
    local line path deps d name
    line=$(grep -E "(^|/)$1\.ko(\.[a-z]+)?:" "$MODDIR/modules.dep" | head -n 1)
    [ -n "$line" ] || { echo "module $1 not in $MODDIR/modules.dep" >&2; return 1; }
    path=${line%%:*}
    deps=${line#*:}
    for d in $deps; do
        name=$(basename "$d"); name=${name%%.ko*}
        grep -qx "$d" "$ORDER" || add_module "$name"
    done
    grep -qx "$path" "$ORDER" || echo "$path" >> "$ORDER"
}
for m in virtio virtio_ring virtio_pci_legacy_dev virtio_pci_modern_dev virtio_pci 9pnet 9pnet_virtio netfs fscache 9p \
         can can-raw can-isotp can-dev vcan; do
    if grep -qE "(^|/)$m\.ko" "$MODDIR/modules.dep"; then add_module "$m"; fi
done
i=0
: > "$ROOT/modules/list"
while read -r path; do
    i=$((i + 1))
    dst=$(printf "%02d_%s" "$i" "$(basename "$path")")
    case "$path" in
        *.xz) xz -dc "$MODDIR/$path" > "$ROOT/modules/${dst%.xz}"; dst=${dst%.xz} ;;
        *.zst) zstd -qdc "$MODDIR/$path" > "$ROOT/modules/${dst%.zst}"; dst=${dst%.zst} ;;
        *) cp "$MODDIR/$path" "$ROOT/modules/$dst" ;;
    esac
    echo "$dst" >> "$ROOT/modules/list"
done < "$ORDER"

cat > "$ROOT/init" <<INIT
#!/bin/busybox sh
/bin/busybox mount -t proc proc /proc
/bin/busybox mount -t sysfs sys /sys
/bin/busybox mount -t devtmpfs dev /dev
for m in \$(/bin/busybox cat /modules/list); do
    /bin/busybox insmod /modules/\$m || echo "insmod \$m failed"
done
/bin/busybox mount -t 9p -o trans=virtio,version=9p2000.L,ro,cache=loose hostroot /host || echo "VCAN_SETUP 9p mount failed"
/bin/busybox mount -t proc proc /host/proc
/bin/busybox mount -t sysfs sys /host/sys
/bin/busybox mount -t devtmpfs dev /host/dev
# /tmp stays the host's (read-only): the checkout and build may live there (CI clones).
/bin/busybox chroot /host /bin/sh -c 'ip link add dev vcan0 type vcan && ip link set vcan0 mtu 72 && ip link set vcan0 up' \
    || echo "VCAN_SETUP creating vcan0 failed"
/bin/busybox chroot /host "$CHECK" vcan0 "$LOG" /usr/bin/canplayer "$DATA/dbc" "$MAP" "$NAVDBC"
echo "VCAN_EXIT=\$?"
if [ -n "$SIM" ]; then
    /bin/busybox mount -t tmpfs run /host/run
    /bin/busybox chroot /host /bin/sh -c '/usr/bin/candump -L vcan0 > /run/sim.log & sleep 0.5; \
        "$SIM" --store "$STORE" --dbc "$NAVDBC" --from "Andorra la Vella" --to Encamp --iface vcan0 --socketcan \
            --speed-factor 0 --duration 2 > /run/sim.out 2>&1; echo "VCAN_SIM_EXIT=\$?"; sleep 0.5; kill %1; \
        echo "VCAN_SIM_FRAMES=\$(grep -c " vcan0 " /run/sim.log) VCAN_SIM_POSITION=\$(grep -c " vcan0 6A0#" /run/sim.log)"'
fi
/bin/busybox poweroff -f
INIT
chmod +x "$ROOT/init"
(cd "$ROOT" && find . | cpio -o -H newc --quiet | gzip -1 > "$WORK/initramfs.gz")

OUT=$WORK/console.log
echo "booting $KERNEL under qemu (TCG), modules: $(tr '\n' ' ' < "$ROOT/modules/list")"
timeout "${NAVMAP_VCAN_TIMEOUT:-90}" "$QEMU" -machine q35,accel=${NAVMAP_VCAN_ACCEL:-tcg} -m 768 -smp 1 -nographic -no-reboot \
    -nic none -kernel "$KERNEL" -initrd "$WORK/initramfs.gz" \
    -append "console=ttyS0 ${NAVMAP_VCAN_KERNEL_ARGS:-quiet loglevel=3} panic=-1 rdinit=/init" \
    -virtfs local,path=/,mount_tag=hostroot,security_model=none,readonly=on \
    > "$OUT" 2>&1 || true
grep -E "VCAN_|insmod|failed|Kernel panic" "$OUT" || true
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
