#!/usr/bin/env bash
# Runs a command inside a container's limits, as Gradescope's default autograder container sets them
# (½ vCPU, 768 MB), and reports what it used: how a lecturer checks that a course's grade fits before
# uploading it (docs/GRADING.md, "Measured under the limits"). Needs root and cgroups; no systemd.
#
#   under_limits.sh [--cpu PERCENT] [--memory MIB] [--pids N] [--report FILE] -- COMMAND [ARG...]
#
#   --cpu PERCENT   CPU bandwidth of one processor: quota PERCENT·1 ms of every 100 ms (default 50)
#   --memory MIB    memory of the whole process tree, page cache included, as a container's
#                   cgroup counts it (default 768); no swap. Past it the kernel's OOM killer ends the
#                   tree's largest process, as in a container
#   --pids N        processes and threads of the tree (default: unlimited, as Gradescope's)
#   --report FILE   also write the report's line to FILE
#
# The cgroup is made below the caller's own (cgroup v2: its cpu.max, memory.max, memory.swap.max and
# pids.max; v1: the cpu, memory, cpuacct and pids hierarchies), so the limits nest inside whatever
# already holds this shell. The report, one line on standard error:
#   under_limits: exit=0 wall_s=61.3 cpu_s=29.8 peak_mib=355.1 oom_kills=0 throttled_s=12.0 cpu=50% memory=768MiB
# cpu_s and peak_mib are the tree's (peak: the cgroup's high-water mark, page cache included). The
# command's exit status is under_limits.sh's.
set -euo pipefail
cpu=50 memory=768 pids="" report=""
die() {
  echo "under_limits: $*" >&2
  exit 2
}
while (($#)); do
  case $1 in
    --cpu) cpu=${2:?}; shift 2 ;;
    --memory) memory=${2:?}; shift 2 ;;
    --pids) pids=${2:?}; shift 2 ;;
    --report) report=${2:?}; shift 2 ;;
    --) shift; break ;;
    *) die "unknown option '$1' (usage: under_limits.sh [--cpu PERCENT] [--memory MIB] [--pids N] -- COMMAND...)" ;;
  esac
done
(($#)) || die "no command after --"
[[ $cpu =~ ^[0-9]+$ ]] && ((cpu >= 1)) || die "--cpu '$cpu' is not a whole percentage of at least 1"
[[ $memory =~ ^[0-9]+$ ]] && ((memory >= 16)) || die "--memory '$memory' is not a whole number of MiB of at least 16"
[[ -z $pids || $pids =~ ^[0-9]+$ ]] || die "--pids '$pids' is not a whole number"
((EUID == 0)) || die "needs root, to make a cgroup"

name=raster-limits-$$
quota_us=$((cpu * 1000))
memory_bytes=$((memory * 1024 * 1024))
declare -a groups=()  # the cgroup folders made, removed at exit

# The folder of this shell's cgroup in hierarchy $1 (v1: its controller's mount; v2: "").
ownGroup() {
  local line
  if [[ -z $1 ]]; then
    line=$(grep '^0::' /proc/self/cgroup)
  else
    line=$(grep -E "^[0-9]+:([^:]*,)?$1(,[^:]*)?:" /proc/self/cgroup)
  fi
  echo "${line#*:*:}"
}
made=""
makeGroup() {  # $1 mount point, $2 controller (v1) or "" (v2): the new group's folder into $made
  made=$1$(ownGroup "$2")/$name
  made=${made//\/\//\/}
  mkdir "$made" || die "cannot make the cgroup $made"
  groups+=("$made")
}
cleanup() {
  local g
  for g in "${groups[@]}"; do rmdir "$g" 2>/dev/null || true; done
}
trap cleanup EXIT

if [[ -f /sys/fs/cgroup/cgroup.controllers ]]; then
  makeGroup /sys/fs/cgroup ""
  v2=$made
  echo "$quota_us 100000" >"$v2/cpu.max" || die "no cpu controller in $v2: enable it in its parent's cgroup.subtree_control, or use systemd-run --scope -p CPUQuota=50% -p MemoryMax=768M"
  echo "$memory_bytes" >"$v2/memory.max" || die "no memory controller in $v2"
  echo 0 >"$v2/memory.swap.max" 2>/dev/null || true
  [[ -z $pids ]] || echo "$pids" >"$v2/pids.max"
  procs=("$v2/cgroup.procs")
else
  for c in cpu memory cpuacct; do
    [[ -d /sys/fs/cgroup/$c ]] || die "no cgroup v1 hierarchy /sys/fs/cgroup/$c"
  done
  makeGroup /sys/fs/cgroup/cpu cpu
  cpu_g=$made
  makeGroup /sys/fs/cgroup/memory memory
  mem_g=$made
  makeGroup /sys/fs/cgroup/cpuacct cpuacct
  acct_g=$made
  echo 100000 >"$cpu_g/cpu.cfs_period_us"
  echo "$quota_us" >"$cpu_g/cpu.cfs_quota_us"
  echo "$memory_bytes" >"$mem_g/memory.limit_in_bytes"
  # No swap: the limit must hold for anonymous memory too (a machine without swap has nothing to set).
  [[ ! -f $mem_g/memory.memsw.limit_in_bytes ]] || echo "$memory_bytes" >"$mem_g/memory.memsw.limit_in_bytes" || true
  procs=("$cpu_g/cgroup.procs" "$mem_g/cgroup.procs" "$acct_g/cgroup.procs")
  if [[ -n $pids ]]; then
    makeGroup /sys/fs/cgroup/pids pids
    pid_g=$made
    echo "$pids" >"$pid_g/pids.max"
    procs+=("$pid_g/cgroup.procs")
  fi
fi

start=$(date +%s.%N)
status=0
# The child enters the groups, then becomes the command: everything it starts stays inside.
bash -c 'for f in "${@:2:$1}"; do echo $$ >"$f"; done; shift $(($1 + 1)); exec "$@"' \
  under_limits "${#procs[@]}" "${procs[@]}" "$@" || status=$?
end=$(date +%s.%N)

if [[ -n ${v2:-} ]]; then
  cpu_us=$(awk '$1 == "usage_usec" {print $2}' "$v2/cpu.stat")
  cpu_s=$(awk -v u="$cpu_us" 'BEGIN {printf "%.1f", u / 1e6}')
  throttled_s=$(awk '$1 == "throttled_usec" {printf "%.1f", $2 / 1e6}' "$v2/cpu.stat")
  peak=$(cat "$v2/memory.peak" 2>/dev/null || echo 0)
  oom=$(awk '$1 == "oom_kill" {print $2}' "$v2/memory.events")
else
  cpu_s=$(awk '{printf "%.1f", $1 / 1e9}' "$acct_g/cpuacct.usage")
  throttled_s=$(awk '$1 == "throttled_time" {printf "%.1f", $2 / 1e9}' "$cpu_g/cpu.stat")
  peak=$(cat "$mem_g/memory.max_usage_in_bytes")
  oom=$(awk '$1 == "oom_kill" {print $2}' "$mem_g/memory.oom_control")
fi
line=$(printf 'under_limits: exit=%d wall_s=%.1f cpu_s=%s peak_mib=%.1f oom_kills=%s throttled_s=%s cpu=%d%% memory=%dMiB' \
  "$status" "$(awk -v a="$start" -v b="$end" 'BEGIN {print b - a}')" "$cpu_s" \
  "$(awk -v p="$peak" 'BEGIN {print p / 1048576}')" "${oom:-0}" "${throttled_s:-0}" "$cpu" "$memory")
echo "$line" >&2
[[ -z $report ]] || echo "$line" >"$report"
exit "$status"
