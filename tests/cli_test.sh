#!/usr/bin/env bash
# raster's command line: every option of every subcommand refuses a bad value (out of range, not a
# number, not one of its choices, missing) with exit status 2 and a message naming the option and
# the value; --help works for each subcommand and lists its options; an unknown option or
# subcommand is refused; good values still work; an error while running (out of memory too) exits 1
# and keeps the files already written.
#   bash tests/cli_test.sh build/bin/raster
set -euo pipefail
raster=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
checked=0

# run STATUS ARGS...: runs raster ARGS (stdout in $tmp/out, stderr in $tmp/err) and expects STATUS.
run() {
  local want=$1 status=0
  shift
  "$raster" "$@" >"$tmp/out" 2>"$tmp/err" || status=$?
  [[ $status == "$want" ]] || fail "raster $*: exit status $status, not $want; stderr: $(cat "$tmp/err")"
  checked=$((checked + 1))
}
# says TEXT: stderr holds TEXT.
says() {
  grep -qF -- "$1" "$tmp/err" || fail "stderr does not say '$1': $(cat "$tmp/err")"
}
# bad OPTION VALUE ARGS...: raster ARGS is a usage error (2) whose message names OPTION and VALUE
# (VALUE empty: a missing value, not checked).
bad() {
  local option=$1 value=$2
  shift 2
  run 2 "$@"
  says "$option"
  [[ -z $value ]] || says "$value"
}

# ---- Values out of range, not numbers, not among the choices, missing ---------------------------
# Whole decimal numbers only (one parser for all the numeric options).
for value in -1 0x10 +5 1.5 1e3 " 5" ""; do bad --width "$value" bench particles --width "$value"; done
# An option for a value: taken as the value, and refused as one.
bad --height --width render fog --height --width 64
for command in "bench particles" "trace particles --stats" "render fog"; do
  # shellcheck disable=SC2086  # $command is the subcommand and its first arguments
  {
    bad --width 0 $command --width 0
    bad --width 16385 $command --width 16385
    bad --width abc $command --width abc
    bad --width "" $command --width
    bad --height 0 $command --height 0
    bad --height x $command --height x
    bad --height "" $command --height
  }
done
for command in "bench particles" "trace particles --stats" "view particles"; do
  # shellcheck disable=SC2086
  {
    bad --count 50000001 $command --count 50000001
    bad --count ten $command --count ten
    bad --count "" $command --count
    bad --seed 4294967296 $command --seed 4294967296
    bad --seed -1 $command --seed -1
    bad --cubes 1025 $command --cubes 1025
    bad --cubes x $command --cubes x
    bad --cubes "" $command --cubes
    bad --fog thick $command --fog thick
    bad --fog "" $command --fog
    bad --threads 0 $command --threads 0
    bad --threads 1025 $command --threads 1025
    bad --threads "" $command --threads
    bad --reference maybe $command --reference=maybe
    bad --plain maybe $command --plain=maybe
  }
done
bad --frames 0 bench particles --frames 0
bad --frames 100001 bench particles --frames 100001
bad --frames "" bench particles --frames
bad --out "" bench particles --out
bad --texture "" bench particles --texture
bad --no-error maybe bench particles --no-error=maybe

bad --out-dir "" render fog --out-dir
# Time: --frames, --fps and --time (render), --time and --seed (bench).
bad --frames 0 render fire --frames 0
bad --frames x render fire --frames x
bad --fps nan render fire --frames 2 --fps nan
bad --fps 0 render fire --frames 2 --fps 0
bad --fps -5 render fire --frames 2 --fps -5
bad --fps inf render fire --frames 2 --fps inf
bad --time -1 render fire --time -1
bad --time nan render fire --time nan
bad --time 601 render fire --time 601
bad --fov 0 render sprites --fov 0
bad --fov 180 render sprites --fov 180
bad --fov nan bench sprites --fov nan
bad --time "" bench fire --time
# The fog scenes' medium (--sigma, --source R,G,B or one number; --falloff B): each component a finite
# float >= 0, else an error naming the option and what is wrong with the value, never a NaN picture.
for command in "render fog-constant" "bench fog-height" "trace fog --stats" "view fog-black"; do
  # shellcheck disable=SC2086
  {
    bad --sigma "--sigma: -1 is negative" $command --sigma -1
    bad --sigma "--sigma: nan is not a number" $command --sigma 0.1,nan,0.1
    bad --source "--source: inf is infinite" $command --source 0.1,0.1,inf
    bad --falloff "--falloff: -0.5 is negative" $command --falloff -0.5
  }
done
bad --sigma "--sigma: 1e+39 is too large for a float" render fog-constant --sigma 1e39
bad --sigma "--sigma: 'x' is not a number" render fog-constant --sigma 0.1,x,0.1
bad --sigma "--sigma: takes R,G,B (or one number for all three), not '0.1,0.2'" render fog --sigma 0.1,0.2
bad --falloff "--falloff: takes one number, not '1,2,3'" render fog-height --falloff 1,2,3
bad --source "" render media-closed-form --source
# Accepted by the option, refused by the scene: q/sigma must be a finite float (the fog's colour).
run 1 render fog-constant --sigma 1e-30 --source 1e9 --width 8 --height 8 --out-dir "$tmp/png"
says "fog source 1e+09 over sigma 1e-30 (channel R) is not a finite float"
# The volume light of the media and cloud scenes (--light point:X,Y,Z or dir:X,Y,Z, --light-intensity):
# each number finite, a direction not 0, three numbers; a scene without a volume light refuses it.
bad --light "--light: 'point:1,2' needs three numbers" render media --light point:1,2
bad --light "--light: 'dir:1,2,3,4' needs three numbers" render media --light dir:1,2,3,4
bad --light "--light: takes point:X,Y,Z or dir:X,Y,Z, not 'sun:1,2,3'" render media --light sun:1,2,3
bad --light "--light: takes point:X,Y,Z or dir:X,Y,Z, not '1,2,3'" render cloud --light 1,2,3
bad --light "--light: nan is not a number" render media --light point:1,nan,2
bad --light "--light: inf is infinite" trace media --stats --light dir:inf,1,0
bad --light "--light: -inf is infinite" view media --light point:0,-inf,0
bad --light "--light: 'x' is not a number" bench media --light point:x,1,2
bad --light "--light: 1e+39 is too large for a float" render media --light point:1e39,0,0
bad --light "--light: 'dir:0,0,0': the direction (0, 0, 0) has no length" render media --light dir:0,0,0
bad --light "" render media --light
bad --light-intensity "--light-intensity: -1 is negative" render media --light-intensity -1
bad --light-intensity "--light-intensity: nan is not a number" render cloud --light-intensity 1,nan,1
# Accepted by the option, refused by the scene: it has no volume light.
run 1 render fog --light point:0,2,0 --width 8 --height 8 --out-dir "$tmp/png"
says "light: scene 'fog' has no volume light (the scenes with one: media, cloud, cloud-point)"
run 1 render fire --light-intensity 2 --width 8 --height 8 --out-dir "$tmp/png"
says "light: scene 'fire' has no volume light"
bad --seed -1 bench fire --seed -1
bad --frames "static" render fog --frames 2
bad --list maybe render --list=maybe
bad --view maybe render fog --view=maybe

bad --pixel 160 trace particles --pixel 160
bad --pixel a,b trace particles --pixel a,b
bad --pixel -1,2 trace particles --pixel -1,2
bad --pixel 16384,0 trace particles --pixel 16384,0
bad --pixel "" trace particles --pixel
bad --pixel 999,999 trace particles --width 320 --height 180 --pixel 999,999
says 320x180
bad --draw x trace particles --draw x
bad --draw 4294967295 trace particles --draw 4294967295
bad --draw "" trace particles --draw
bad --limit 1048577 trace particles --draw 0 --limit 1048577
bad --limit "" trace particles --draw 0 --limit
bad --json "" trace particles --stats --json
bad --stats "" trace particles
bad --stats maybe trace particles --stats=maybe

bad --size 0x10 view particles --size 0x10
bad --size 320 view particles --size 320
bad --size 320x view particles --size 320x
bad --size 16385x10 view particles --size 16385x10
bad --size "" view particles --size
bad --script Z view particles --script "N ] Z"
bad --script "" view particles --script
bad --screenshot-dir "''" view particles --screenshot-dir ""
bad --screenshot-dir "" view particles --screenshot-dir
bad --solution smog view particles --solution smog
bad --solution lab.jpg view particles --solution lab.jpg
bad --solution "''" view particles --solution ""
bad --solution "" view particles --solution
bad --headless maybe view particles --headless=maybe
bad --screenshot-window maybe view particles --screenshot-window=maybe

# The scene: missing or unknown.
for command in bench trace view; do
  bad scene "" "$command"
  bad scene smog "$command" smog
done
bad scene smog render fog smog
# microbench hands its arguments to Google Benchmark, which refuses what it does not know.
bad --bogus "" microbench --bogus
# grade: the submission must be a folder; its numbers and choices are checked like the others'.
bad submission "" grade
bad submission "/nonexistent" grade /nonexistent
bad --jobs 0 grade "$tmp" --jobs 0
bad --path fastest grade "$tmp" --path fastest
run 1 grade "$tmp" --lab nosuchlab --out "$tmp/grade"
says "--lab nosuchlab: no lab of that name"

# ---- Unknown options and subcommands ------------------------------------------------------------
for command in "bench particles" "render fog" "trace particles --stats" "view particles"; do
  # shellcheck disable=SC2086
  bad --bogus "" $command --bogus
  # shellcheck disable=SC2086
  bad -x "" $command -x
done
bad smog "" smog
says "raster --help lists the commands"
bad --bogus "" --bogus
run 2
says "Subcommands:"

# ---- --help: exit 0, every option listed ----------------------------------------------------------
# helps COMMAND OPTION...: raster COMMAND --help lists each OPTION.
helps() {
  local command=$1
  shift
  run 0 "$command" --help
  for option in "$@"; do
    grep -qF -- "$option" "$tmp/out" || fail "raster $command --help does not list $option"
  done
}
helps bench --width --height --fov --count --seed --cubes --fog --time --texture --frames --threads --out --reference --plain \
  --no-error --turbulence particles-sim
helps render --out-dir --width --height --fov --count --seed --time --frames --fps --reference --plain --view --list \
  --sigma --source --falloff --light --light-intensity
helps trace --stats --pixel --json --draw --limit --width --height --fov --count --seed --cubes --fog --threads --reference --plain
helps view --size --count --seed --cubes --fog --threads --reference --plain --headless --script --screenshot-dir \
  --screenshot-window --solution "keys:"
helps microbench --benchmark_filter "Google Benchmark"
helps grade --lab --out --public --jobs --threads --path --render-seconds --render-memory --build-seconds \
  --grading-root --toolchain --keep-scratch
run 0 --help
for command in bench grade microbench render trace view; do grep -q "^  $command " "$tmp/out" || fail "raster --help lacks $command"; done
run 0 help
grep -q "^  view " "$tmp/out" || fail "raster help lacks view"

# ---- Good values still work -------------------------------------------------------------------------
# png_size FILE: "WxH" from the PNG's IHDR (width, height at bytes 16..23).
png_size() {
  local hex
  hex=$(od -An -tx1 -j16 -N8 "$1" | tr -d ' \n')
  echo "$((16#${hex:0:8}))x$((16#${hex:8:8}))"
}
run 0 render fog --width 64 --height 48 --out-dir "$tmp/png"
[[ $(png_size "$tmp/png/fog.png") == 64x48 ]] || fail "render fog --width 64 --height 48 wrote $(png_size "$tmp/png/fog.png")"
# Leading zeros are decimal, and a repeated option takes its last value.
run 0 render fog --width 010 --height 32 --height 008 --out-dir "$tmp/png"
[[ $(png_size "$tmp/png/fog.png") == 10x8 ]] || fail "--width 010 --height 32 --height 008 wrote $(png_size "$tmp/png/fog.png")"
run 0 bench fog --width 64 --height 36 --frames 1 --no-error --cubes 2 --fog constant
grep -q '^raster fog 64x36 ms_per_frame_median=[0-9.]* frames=1$' "$tmp/out" || fail "bench printed: $(cat "$tmp/out")"
# Without --no-error, the fast pipeline's error against the reference comes first (raster::compareImages
# over RGB): its figures agree with one another.
run 0 bench fog --width 64 --height 36 --frames 1 --cubes 2 --fog constant
error=$(grep -E '^error_vs_reference mean_abs=[0-9]+\.[0-9]{4} max_diff=[0-9]+ within_1=[01]\.[0-9]{6}$' "$tmp/out") ||
  fail "bench printed no error line: $(cat "$tmp/out")"
read -r max within <<<"$(sed 's/.*max_diff=\([0-9]*\) within_1=\(.*\)/\1 \2/' <<<"$error")"
((max <= 255)) || fail "max_diff $max is more than 255: $error"
if ((max <= 1)); then [[ $within == 1.000000 ]] || fail "max_diff $max but not every pixel within 1: $error"; fi
if ((max == 0)); then [[ $error == *mean_abs=0.0000* ]] || fail "max_diff 0 but a mean difference: $error"; fi
# The fog figures with a medium of the command line's, sigma 0 in one channel included.
run 0 render fog-constant fog-height media-closed-form --sigma 0.05,0,0.07 --source 0.03,0.004,0.05 --falloff 0 \
  --width 48 --height 27 --cubes 2 --out-dir "$tmp/png"
[[ $(png_size "$tmp/png/fog-height.png") == 48x27 ]] || fail "render fog-height with a medium wrote no picture"
# A point light in the media scene: the same picture at 1, 2 and 8 threads; SCENES.md's own light given
# as --light is the scene's picture; the cloud with a point light and an intensity renders.
for threads in 1 2 8; do
  run 0 render media --light point:0.8,1.6,0.6 --light-intensity 30,28,24 --width 64 --height 36 --threads "$threads" \
    --out-dir "$tmp/light$threads"
done
cmp -s "$tmp/light1/media.png" "$tmp/light2/media.png" || fail "media --light point: 1 and 2 threads differ"
cmp -s "$tmp/light1/media.png" "$tmp/light8/media.png" || fail "media --light point: 1 and 8 threads differ"
run 0 render media --width 64 --height 36 --out-dir "$tmp/own"
run 0 render media --light dir:0.4,1,0.3 --width 64 --height 36 --out-dir "$tmp/own-as-option"
cmp -s "$tmp/own/media.png" "$tmp/own-as-option/media.png" ||
  fail "media --light dir:0.4,1,0.3 is not the scene's picture"
cmp -s "$tmp/own/media.png" "$tmp/light1/media.png" && fail "media --light point: the scene's own picture"
run 0 render cloud cloud-point --light point:0,2,-3 --voxels 32 --width 48 --height 27 --out-dir "$tmp/png"
# The particle simulation alone: --count particles, all alive, stepped --frames times.
run 0 bench particles-sim --count 5000 --frames 3 --threads 2 --turbulence
grep -q '^threads=2 alive=5000 ' "$tmp/out" || fail "bench particles-sim printed: $(cat "$tmp/out")"
grep -q '^raster particles-sim count=5000 turbulence=1 ms_per_step_median=[0-9.]* steps=3$' "$tmp/out" ||
  fail "bench particles-sim printed: $(cat "$tmp/out")"
run 1 bench particles-sim --count 0
says "particles-sim needs --count of at least 1"
# render --frames: N files <scene>_0000.png ..., frame k at --time + k/--fps: frame 1 of a sequence
# from 0.4 s at 10 frames a second is the picture at 0.5 s, bit for bit; frames 0 and 1 differ.
run 0 render fire --frames 3 --fps 10 --time 0.4 --width 48 --height 32 --count 300 --out-dir "$tmp/frames"
for k in 0000 0001 0002; do
  [[ $(png_size "$tmp/frames/fire_$k.png") == 48x32 ]] || fail "render --frames 3 did not write fire_$k.png"
done
[[ ! -e $tmp/frames/fire_0003.png && ! -e $tmp/frames/fire.png ]] || fail "render --frames 3 wrote more: $(ls "$tmp/frames")"
run 0 render fire --time 0.5 --width 48 --height 32 --count 300 --out-dir "$tmp/frames"
cmp -s "$tmp/frames/fire.png" "$tmp/frames/fire_0001.png" || fail "frame 1 from 0.4 s at 10 fps is not the picture at 0.5 s"
! cmp -s "$tmp/frames/fire_0000.png" "$tmp/frames/fire_0001.png" || fail "frames 0 and 1 of the fire are the same"
# --frames without a scene: the animated ones only.
run 0 render --frames 1 --width 16 --height 16 --out-dir "$tmp/anim"
animated="fire_0000.png forest_0000.png particle-system@solution_0000.png particle-system_0000.png smoke-volume_0000.png"
animated+=" smoke_0000.png"
animated+=" sprite-methods@solution_0000.png sprite-methods_0000.png sprites_0000.png "
[[ $(LC_ALL=C ls "$tmp/anim" | tr '\n' ' ') == "$animated" ]] ||
  fail "render --frames 1 wrote $(ls "$tmp/anim")"
run 0 bench fire --width 64 --height 36 --frames 2 --count 200 --time 1 --seed 3 --no-error
grep -q '^raster fire 64x36 ms_per_frame_median=[0-9.]* frames=2$' "$tmp/out" || fail "bench fire printed: $(cat "$tmp/out")"
run 0 trace particles --count 20 --width 64 --height 36 --pixel 32,18 --json --threads 1
grep -q '^{"pixel":\[32,18\]' "$tmp/out" || fail "trace --pixel 32,18 --json printed: $(head -c 200 "$tmp/out")"
run 0 render --list
grep -q '^particles ' "$tmp/out" || fail "render --list lacks particles"
[[ $(head -n 1 "$tmp/out") == fire\ * ]] || fail "render --list does not begin with fire"
SDL_VIDEODRIVER=offscreen run 0 view particles --headless --size 64x36 --count 20 --script "N S" \
  --screenshot-dir "$tmp/shots"
[[ $(png_size "$tmp/shots/particles-0001.png") == 64x36 ]] || fail "view --size 64x36 saved another size"

# ---- Errors while running: exit 1; what was written stays ----------------------------------------
run 1 bench particles --width 64 --height 36 --texture "$tmp/missing.png"
says "raster bench: bad file: "
mkdir -p "$tmp/keep/fog.png"  # a directory where render wants to write fog's PNG
run 1 render particles fog --width 32 --height 18 --out-dir "$tmp/keep"
says "raster render: "
[[ $(png_size "$tmp/keep/particles.png") == 32x18 ]] || fail "render lost particles.png after fog's error"
grep -qF "wrote $tmp/keep/particles.png" "$tmp/out" || fail "render did not say it wrote particles.png"
# Out of memory (a 16384x16384 target under a 1 GB address-space limit) is an error, not a crash.
# AddressSanitizer reserves far more address space than that: skipped in such a build.
if ! grep -qa __asan_init "$raster"; then
  (
    ulimit -v 1000000
    run 1 render fog --width 16384 --height 16384 --out-dir "$tmp/big"
  )
  grep -qi "^raster render: out of memory" "$tmp/err" || fail "no out-of-memory message: $(cat "$tmp/err")"
fi
echo "raster CLI: $checked command lines checked"
