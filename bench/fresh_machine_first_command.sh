#!/usr/bin/env bash
# Times the README's first set-up command (scripts/run_sample.sh) on a fresh Debian 12: a minimal
# bookworm made by debootstrap in WORK_DIR, this checkout's HEAD cloned into it, and the command
# run there as root, so that every package it needs is downloaded and installed as on a new
# machine. Prints the wall time, when the build was configured and when `bouncecal` was linked
# (both seconds after the start: before the first, apt-get; between them, the compiler), the CPU
# time of everything it ran, and the end of its output. Needs root, debootstrap and the network
# to a Debian mirror; the host should be otherwise idle (another process's load is not held off
# by a nice level across cgroups).
#
#   sudo bench/fresh_machine_first_command.sh [WORK_DIR]     (default: a new folder under /tmp)
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
work="${1:-$(mktemp -d /tmp/bouncecal_fresh.XXXXXX)}"
root="${work}/root"
mkdir -p "${work}"
mirror="${BOUNCECAL_DEBIAN_MIRROR:-http://deb.debian.org/debian}"
[ "$(id -u)" -eq 0 ] || { echo "fresh_machine_first_command.sh: run as root" >&2; exit 1; }
command -v debootstrap >/dev/null || { echo "fresh_machine_first_command.sh: install debootstrap" >&2; exit 1; }

unmount() { for m in dev/pts dev proc; do umount "${root}/${m}" 2>/dev/null || true; done; }
trap unmount EXIT

echo "debootstrap (minbase bookworm) into ${root} ..."
debootstrap --variant=minbase bookworm "${root}" "${mirror}" >"${work}/debootstrap.log" 2>&1
cp /etc/resolv.conf "${root}/etc/resolv.conf"
mount -t proc proc "${root}/proc"
mount --bind /dev "${root}/dev"
mount --bind /dev/pts "${root}/dev/pts"
git clone -q "${repo}" "${root}/root/bouncecal"
echo "commit $(git -C "${repo}" rev-parse --short HEAD); host load before: $(cut -d' ' -f1-3 /proc/loadavg)"
status=0
chroot "${root}" /usr/bin/env -i HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin TERM=xterm \
  bash -c 'cd /root/bouncecal
    start=$(date +%s.%N)
    scripts/run_sample.sh >/root/run_sample.out 2>&1; status=$?
    end=$(date +%s.%N)
    configured=$(stat -c %Y build/CMakeCache.txt 2>/dev/null || echo 0)
    linked=$(stat -c %Y build/apps/bouncecal 2>/dev/null || echo 0)
    awk -v s="$start" -v e="$end" -v c="$configured" -v l="$linked" -v st="$status" "BEGIN {
      printf \"scripts/run_sample.sh: exit %d, %.1f s wall; configured at +%.0f s, bouncecal linked at +%.0f s\n\",
        st, e - s, c - s, l - s }"
    echo "CPU (user, system) of the shell, then of everything it ran:"; times
    exit $status' || status=$?
echo "host load after: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "--- the end of its output"
tail -n 12 "${root}/root/run_sample.out"
exit "${status}"
