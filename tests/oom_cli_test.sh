#!/usr/bin/env bash
# Out of memory on the command line: under an address-space limit (ulimit -v) the program exits 1
# with a message naming what could not be allocated and how much, instead of aborting on
# std::bad_alloc (exit 134), and files it wrote before stay.
#   bash tests/oom_cli_test.sh build/bin/raster
# Exit 77 (skipped) under AddressSanitizer, which needs far more address space than any such limit.
set -uo pipefail
raster=$1
# (Not `nm | grep -q` under pipefail: grep stops at the first match, nm dies of SIGPIPE, and the
# pipeline fails, which read as "no ASan" until 2026-12-03.)
if grep -q __asan_init < <(nm "$raster" 2>/dev/null); then
  echo "skipped: built with AddressSanitizer"
  exit 77
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# A 16384x16384 frame: 1 GiB of colour and 1 GiB of depth do not fit in 2 GB with the program.
(ulimit -v 2000000 && "$raster" render fog --width 16384 --height 16384 --out-dir "$dir") >"$dir/out.txt" 2>"$dir/err.txt"
status=$?
cat "$dir/err.txt"
[[ $status == 1 ]] || fail "render at 16384x16384 under 2 GB exited $status, not 1"
grep -q "out of memory" "$dir/err.txt" || fail "the message does not say out of memory"
grep -q "16384x16384" "$dir/err.txt" || fail "the message does not name the target's size"
grep -qE "GiB \([0-9]+ bytes\)" "$dir/err.txt" || fail "the message does not say how much"

# What was written before the failure stays: a first scene small enough, then one that is not.
(ulimit -v 2000000 && "$raster" render fog --width 64 --height 48 --out-dir "$dir") >/dev/null 2>&1 ||
  fail "a 64x48 render failed under 2 GB"
[[ -s $dir/fog.png ]] || fail "the 64x48 render wrote no fog.png"
cp "$dir/fog.png" "$dir/fog-before.png"
(ulimit -v 2000000 && "$raster" render fog --width 16384 --height 16384 --out-dir "$dir") >/dev/null 2>&1
cmp -s "$dir/fog.png" "$dir/fog-before.png" || fail "a failed render changed the fog.png written before"

# 50 million particles under 4 GB: the particles' arrays do not fit beside the frame.
(ulimit -v 4000000 && "$raster" bench particles --count 50000000 --frames 1 --no-error) >"$dir/out.txt" 2>"$dir/err.txt"
status=$?
cat "$dir/err.txt"
[[ $status == 1 ]] || fail "bench particles --count 50000000 under 4 GB exited $status, not 1"
grep -q "out of memory" "$dir/err.txt" || fail "the message does not say out of memory"
grep -qE "[0-9.]+ (MiB|GiB) \([0-9]+ bytes\)" "$dir/err.txt" || fail "the message does not say how much"
echo "oom_cli: all checks passed"
