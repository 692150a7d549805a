#!/bin/sh
# SPDX-License-Identifier: Apache-2.0
# Runs a command in a Debian kernel under qemu (TCG, no KVM needed), with kernel modules the host
# kernel lacks or cannot load here: the guest loads MODULES (and what they depend on) from the
# host's /lib/modules, mounts the host root read-only over virtio-9p, and runs COMMAND there
# (chroot, /run a tmpfs and HOME, the output on the console). The exit status is COMMAND's.
#
# usage: run_in_guest.sh "<modules>" <command> [args...]
#        e.g. run_in_guest.sh vgem env NAVMAP_EXPECT_DMABUF=1 build/tests/render/render_gpu_tests
# exit:  COMMAND's status; 77 skipped (qemu, the kernel or busybox missing: the reason is printed);
#        1 when the guest did not finish.
# env:   NAVMAP_GUEST_KERNEL (default: newest /boot/vmlinuz-*), NAVMAP_GUEST_TIMEOUT (s, default
#        300), NAVMAP_GUEST_MEMORY (MiB, default 2048), NAVMAP_GUEST_ACCEL (qemu accelerator, default tcg)
set -eu

skip() { echo "SKIPPED: $*"; exit 77; }
fail() { echo "FAIL: $*"; exit 1; }
[ "$#" -ge 2 ] || fail "usage: $0 \"<modules>\" <command> [args...]"
MODULES=$1
shift

QEMU=$(command -v qemu-system-x86_64 || true)
[ -n "$QEMU" ] || skip "qemu-system-x86_64 not found (apt-get install qemu-system-x86)"
KERNEL=${NAVMAP_GUEST_KERNEL:-$(ls -1 /boot/vmlinuz-* 2>/dev/null | sort -V | tail -n 1)}
[ -n "$KERNEL" ] && [ -r "$KERNEL" ] || skip "no readable /boot/vmlinuz-* (apt-get install linux-image-amd64)"
KVER=${KERNEL#*/vmlinuz-}
MODDIR=/lib/modules/$KVER
[ -r "$MODDIR/modules.dep" ] || skip "$MODDIR/modules.dep missing for kernel $KVER"
BUSYBOX=$(command -v busybox || true)
[ -n "$BUSYBOX" ] || skip "busybox not found (apt-get install busybox-static)"
file -L "$BUSYBOX" 2>/dev/null | grep -q "statically linked" || [ -x /bin/busybox ] || skip "busybox is not static"
command -v cpio >/dev/null || skip "cpio not found"

WORK=$(mktemp -d /tmp/navmap-guest.XXXXXX)
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
for m in virtio virtio_ring virtio_pci_legacy_dev virtio_pci_modern_dev virtio_pci 9pnet 9pnet_virtio netfs fscache 9p; do
    if grep -qE "(^|/)$m\.ko" "$MODDIR/modules.dep"; then add_module "$m"; fi
done
for m in $MODULES; do add_module "$m" || skip "kernel $KVER has no module $m"; done
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

# The command, each argument quoted for the guest's shell, run in the current directory, with the
# sanitizers' settings of the caller (scripts/test-sanitizers.sh runs guest tests too).
CMD="cd '$(pwd)' &&"
for v in ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS; do
    eval "val=\${$v:-}"
    [ -z "$val" ] || CMD="$CMD export $v='$val' &&"
done
for a in "$@"; do CMD="$CMD '$(printf '%s' "$a" | sed "s/'/'\\\\''/g")'"; done
cat > "$ROOT/init" <<INIT
#!/bin/busybox sh
/bin/busybox mount -t proc proc /proc
/bin/busybox mount -t sysfs sys /sys
/bin/busybox mount -t devtmpfs dev /dev
for m in \$(/bin/busybox cat /modules/list); do
    /bin/busybox insmod /modules/\$m || echo "GUEST_SETUP insmod \$m failed"
done
/bin/busybox mount -t 9p -o trans=virtio,version=9p2000.L,ro,cache=loose hostroot /host || echo "GUEST_SETUP 9p mount failed"
/bin/busybox mount -t proc proc /host/proc
/bin/busybox mount -t sysfs sys /host/sys
/bin/busybox mount -t devtmpfs dev /host/dev
/bin/busybox mount -t tmpfs run /host/run
/bin/busybox chroot /host /bin/sh -c 'export HOME=/run TMPDIR=/run MESA_SHADER_CACHE_DISABLE=true; $CMD'
echo "GUEST_EXIT=\$?"
/bin/busybox poweroff -f
INIT
chmod +x "$ROOT/init"
(cd "$ROOT" && find . | cpio -o -H newc --quiet | gzip -1 > "$WORK/initramfs.gz")

OUT=$WORK/console.log
echo "booting $KERNEL under qemu (TCG), modules: $(tr '\n' ' ' < "$ROOT/modules/list")"
timeout "${NAVMAP_GUEST_TIMEOUT:-300}" "$QEMU" -machine "q35,accel=${NAVMAP_GUEST_ACCEL:-tcg}" -cpu max -m "${NAVMAP_GUEST_MEMORY:-2048}" \
    -smp 2 -nographic -no-reboot -nic none -kernel "$KERNEL" -initrd "$WORK/initramfs.gz" \
    -append "console=ttyS0 quiet loglevel=3 panic=-1 rdinit=/init" \
    -virtfs local,path=/,mount_tag=hostroot,security_model=none,readonly=on,multidevs=remap \
    > "$OUT" 2>&1 || true
# The console without the firmware's escape sequences and the kernel's own lines.
sed -e 's/\x1b\[[0-9;?]*[a-zA-Z]//g' -e '/^\[ *[0-9]*\.[0-9]*\]/d' "$OUT" | grep -v '^SeaBIOS\|^Booting from' || true
status=$(sed -n 's/.*GUEST_EXIT=\([0-9]*\).*/\1/p' "$OUT" | tail -n 1)
[ -n "$status" ] || fail "the guest did not finish (boot or 9p problem, or timeout)"
exit "$status"
