#!/usr/bin/env bash
# Runs each libFuzzer target for a while on its kept corpus (docs/TESTING.md, "Fuzzing").
#
#   tests/fuzz/run.sh <build-dir> <seconds> [--merge] [target ...]
#
# <build-dir> was configured with -DRASTER_FUZZ=ON (clang); <seconds> is each target's time.
# Targets: fuzz_draw fuzz_png fuzz_fog (default: all three, one after the other, one process each,
# under nice). New inputs go to a scratch folder, never straight into the kept corpus; with --merge
# the ones that add coverage are merged into tests/fuzz/corpus/<target>/ at the end (libFuzzer
# -merge=1), so the corpus only grows when asked. A crash, a sanitizer report or a broken contract
# leaves its input in <build-dir>/fuzz-artifacts/<target>/ (printed) and makes the script exit 1.
# Extra libFuzzer flags may come through FUZZ_FLAGS, e.g. FUZZ_FLAGS="-jobs=2".
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
if (($# < 2)); then
  sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
build="$(cd "$1" && pwd)"
seconds="$2"
shift 2
merge=0
targets=()
for a in "$@"; do
  case "$a" in
    --merge) merge=1 ;;
    fuzz_draw | fuzz_png | fuzz_fog) targets+=("$a") ;;
    *) echo "run.sh: unknown argument '$a'" >&2; exit 2 ;;
  esac
done
((${#targets[@]})) || targets=(fuzz_draw fuzz_png fuzz_fog)

# Longest input per target: enough for the decoders' choices, small enough to keep runs fast.
declare -A max_len=([fuzz_draw]=4096 [fuzz_png]=4096 [fuzz_fog]=512)
failed=0
for t in "${targets[@]}"; do
  bin="$build/bin/$t"
  [[ -x $bin ]] || bin="$build/tests/fuzz/$t"
  if [[ ! -x $bin ]]; then
    echo "run.sh: $t is not built in $build (cmake --build $build --target $t)" >&2
    exit 2
  fi
  corpus="$here/corpus/$t"
  scratch="$build/fuzz-scratch/$t"
  artifacts="$build/fuzz-artifacts/$t"
  mkdir -p "$corpus" "$scratch" "$artifacts"
  log="$build/fuzz-$t.log"
  echo "run.sh: $t for ${seconds} s (log $log)"
  set +e
  # shellcheck disable=SC2086
  nice -n 10 "$bin" "$scratch" "$corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len="${max_len[$t]}" -print_final_stats=1 -artifact_prefix="$artifacts/" ${FUZZ_FLAGS:-} >"$log" 2>&1
  rc=$?
  set -e
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  secs=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 || true)
  echo "run.sh: $t: exit $rc, ${runs:-?} executions, ${secs:-?} per second, ${cov:-cov: ?}"
  if ((rc != 0)); then
    failed=1
    grep -m1 -E 'ERROR: |contract broken|runtime error|Test unit written' "$log" || true
    ls -1 "$artifacts" | sed "s|^|run.sh:   $artifacts/|"
  fi
  if ((merge)); then
    nice -n 10 "$bin" -merge=1 -timeout=10 -rss_limit_mb=2048 -max_len="${max_len[$t]}" -artifact_prefix="$artifacts/" \
      "$corpus" "$scratch" >"$build/fuzz-$t-merge.log" 2>&1 || { echo "run.sh: merge of $t failed" >&2; failed=1; }
    echo "run.sh: $t corpus now $(ls "$corpus" | wc -l) files, $(du -sk "$corpus" | cut -f1) KB"
  fi
done
exit "$failed"
