#!/usr/bin/env bash
# raster view in a real window: SDL's x11 driver on a virtual X server (xvfb-run). Steps through the
# particles scene, clicks pixels (each prints its colour and, from a traced render, its history),
# takes screenshots of the frame, the current primitive's wireframe, the overdraw view, and the
# reference pipeline's image and difference (--solution reference, K and J), then runs
# the same script headless; the screenshots and everything printed about the clicks must be the
# same, byte for byte. Then a lab (billboards): K and J compare it with its solution, unasked, in the
# window as headless. Exit 77 (CTest: skipped) only when xvfb-run is missing.
#   bash tests/viewer_xvfb_test.sh build/bin/raster
set -euo pipefail
raster=$1
if ! command -v xvfb-run >/dev/null; then
  echo "xvfb-run is missing (Debian: xvfb, xauth): skipped"
  exit 77
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}

script="N ] ] ] [ P N 0 N ] click:160,90 S 0 click:160,90 click:20,20 S C N ] ] ] L S L O S O 0 K S K J S J Esc"
# The window run must not inherit a headless driver from the caller's environment.
SDL_VIDEODRIVER=x11 timeout 50 xvfb-run -a -s "-screen 0 640x480x24" \
  "$raster" view particles --size 320x180 --script "$script" --screenshot-dir "$dir/window" \
  --screenshot-window --solution reference >"$dir/window.txt"
env -u SDL_VIDEODRIVER timeout 50 "$raster" view particles --headless --size 320x180 --script "$script" \
  --screenshot-dir "$dir/headless" --solution reference >"$dir/headless.txt"
cat "$dir/window.txt"

grep -q "video driver x11" "$dir/window.txt" || fail "the window run did not use SDL's x11 driver"
grep -q "video driver offscreen" "$dir/headless.txt" || fail "the headless run did not use SDL's offscreen driver"
# Click reports and pixel histories: every line but the driver's and the screenshots' paths.
printed() { grep -v -e '^raster view:' -e '^screenshot ' -e '^window ' "$1"; }
diff <(printed "$dir/window.txt") <(printed "$dir/headless.txt") || fail "click reports or histories differ"
[[ $(grep -c '^pixel [0-9]' "$dir/window.txt") == 3 ]] || fail "expected three click reports"
[[ $(grep -c '^pixel ([0-9]*, [0-9]*): [0-9]* fragment' "$dir/window.txt") == 3 ]] ||
  fail "expected three pixel histories"
grep -q '^pixel (160, 90): 2 fragments$' "$dir/window.txt" || fail "pixel 160,90 at draw 2 primitive 1: the occluder and a particle"
grep -q '^difference from the reference pipeline: [0-9]* of 57600 pixels differ' "$dir/window.txt" ||
  fail "J printed no difference from the reference pipeline"
for shot in particles-000{1,2,3,4,5,6}.png; do
  [[ -s $dir/window/$shot ]] || fail "the window run wrote no $shot"
  cmp "$dir/window/$shot" "$dir/headless/$shot" || fail "$shot differs between the window and headless"
done
cmp -s "$dir/window/particles-0001.png" "$dir/window/particles-0002.png" &&
  fail "a stepped frame and the whole frame should differ"
# The window itself was read back: a PNG of the window's size (IHDR: width, height at bytes 16..23).
size=$(od -An -tx1 -j16 -N8 "$dir/window/particles-0001-window.png" | tr -d ' \n')
[[ $size == 00000140000000b4 ]] || fail "window capture is not 320x180 (IHDR $size)"

# A lab: its solution (billboards@solution) is what K shows and J compares with, without --solution.
lab_script="J S K S Esc"
SDL_VIDEODRIVER=x11 timeout 50 xvfb-run -a -s "-screen 0 640x480x24" \
  "$raster" view billboards --size 320x180 --script "$lab_script" --screenshot-dir "$dir/lab-window" >"$dir/lab-window.txt"
env -u SDL_VIDEODRIVER timeout 50 "$raster" view billboards --headless --size 320x180 --script "$lab_script" \
  --screenshot-dir "$dir/lab-headless" >"$dir/lab-headless.txt"
cat "$dir/lab-window.txt"
grep -q "video driver x11" "$dir/lab-window.txt" || fail "the lab's window run did not use SDL's x11 driver"
grep -q '^difference from scene billboards@solution: [0-9]* of 57600 pixels differ' "$dir/lab-window.txt" ||
  fail "J on a lab printed no difference from its solution"
diff <(printed "$dir/lab-window.txt") <(printed "$dir/lab-headless.txt") || fail "the lab's reports differ"
for shot in billboards-000{1,2}.png; do
  [[ -s $dir/lab-window/$shot ]] || fail "the lab's window run wrote no $shot"
  cmp "$dir/lab-window/$shot" "$dir/lab-headless/$shot" || fail "lab $shot differs between the window and headless"
done
cmp -s "$dir/lab-window/billboards-0001.png" "$dir/lab-window/billboards-0002.png" &&
  fail "the lab's difference and its solution's image should differ"
echo "viewer under Xvfb: OK"
