#!/usr/bin/env bash
# raster/tools/grade/gradescope/under_limits.sh holds a command to its limits and reports what it used:
# a tree past --memory loses its largest process to the OOM killer (exit 137, oom_kills=1), a busy
# loop gets no more CPU than --cpu allows, the exit status is the command's, bad options are refused.
# Exit 77 (CTest: skipped) where it cannot run: not root, or no cgroups to make.
#   bash tests/under_limits_test.sh raster/tools/grade/gradescope/under_limits.sh
set -euo pipefail
limits=$1
if ((EUID != 0)); then
  echo "not root: cannot make a cgroup: skipped"
  exit 77
fi
if [[ ! -f /sys/fs/cgroup/cgroup.controllers && ! -d /sys/fs/cgroup/memory ]]; then
  echo "no cgroup v2 nor v1 memory hierarchy: skipped"
  exit 77
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
field() { grep -o "$2=[0-9.]*" "$1" | cut -d= -f2; }

# 200 MiB touched page by page under a 64 MiB limit.
status=0
bash "$limits" --memory 64 --report "$dir/oom.txt" -- \
  python3 -c "b = bytearray(200 << 20); b[::4096] = b'1' * len(b[::4096])" 2>/dev/null || status=$?
cat "$dir/oom.txt"
[[ $status == 137 ]] || fail "200 MiB under a 64 MiB limit exited $status, not 137 (killed)"
[[ $(field "$dir/oom.txt" oom_kills) -ge 1 ]] || fail "no OOM kill counted"
awk -v p="$(field "$dir/oom.txt" peak_mib)" 'BEGIN {exit !(p <= 64.5)}' || fail "the peak is past the limit"

# The same allocation fits under 512 MiB: the limit, not the allocation, killed it.
bash "$limits" --memory 512 --report "$dir/fits.txt" -- \
  python3 -c "b = bytearray(200 << 20); b[::4096] = b'1' * len(b[::4096])" 2>/dev/null ||
  fail "200 MiB under a 512 MiB limit failed"
awk -v p="$(field "$dir/fits.txt" peak_mib)" 'BEGIN {exit !(p >= 200 && p <= 512)}' ||
  fail "peak $(field "$dir/fits.txt" peak_mib) MiB for a 200 MiB allocation"

# Two busy processes for 2 s under 25 % of one processor: at most a quarter of the wall time in CPU
# (the quota is enforced per 100 ms period; a period's slack allowed).
status=0
bash "$limits" --cpu 25 --report "$dir/cpu.txt" -- \
  bash -c 'timeout 2 sh -c "while :; do :; done" & timeout 2 sh -c "while :; do :; done"; wait' 2>/dev/null || status=$?
cat "$dir/cpu.txt"
awk -v c="$(field "$dir/cpu.txt" cpu_s)" -v w="$(field "$dir/cpu.txt" wall_s)" 'BEGIN {exit !(c <= 0.25 * w + 0.15 && c > 0)}' ||
  fail "CPU $(field "$dir/cpu.txt" cpu_s) s in $(field "$dir/cpu.txt" wall_s) s under a 25 % quota"

# The command's status is passed on; bad options are refused with status 2, naming the option.
status=0
bash "$limits" -- sh -c 'exit 3' 2>/dev/null || status=$?
[[ $status == 3 ]] || fail "exit 3 came back as $status"
status=0
bash "$limits" --cpu 0 -- true 2>"$dir/err.txt" || status=$?
[[ $status == 2 ]] && grep -q -- "--cpu '0'" "$dir/err.txt" || fail "--cpu 0 was not refused by name"
status=0
bash "$limits" --memory 64 2>"$dir/err.txt" || status=$?
[[ $status == 2 ]] && grep -q "no command" "$dir/err.txt" || fail "a missing command was not refused"
# No cgroup is left behind.
leftover=$(find /sys/fs/cgroup -maxdepth 6 -type d -name 'raster-limits-*' 2>/dev/null | head -n 1)
[[ -z $leftover ]] || fail "cgroup left behind: $leftover"
echo "under_limits: all checks passed"
