#!/usr/bin/env bash
# raster trace on the command line: a pixel's history as a table and as JSON list the same fragments;
# a pixel outside the target and a draw past the frame's last are refused, naming what was asked for.
#   bash tests/trace_cli_test.sh build/bin/raster
set -euo pipefail
raster=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
scene=(particles --count 500 --width 320 --height 180)

# --pixel: the table's header count, its rows and the JSON's fragments agree (and are not zero:
# the pixel is on the occluder, under particles).
"$raster" trace "${scene[@]}" --pixel 160,100 >"$dir/table.txt"
"$raster" trace "${scene[@]}" --pixel 160,100 --json >"$dir/history.json"
cat "$dir/table.txt"
header=$(sed -n '1s/^pixel (160, 100): \([0-9]*\) fragments\?$/\1/p' "$dir/table.txt")
[[ -n $header ]] || fail "the table's first line is not 'pixel (160, 100): N fragments'"
rows=$(grep -cE '^ +[0-9]+ +[0-9]+ +[0-9.]+ ' "$dir/table.txt" || true)
json=$(grep -o '"draw":' "$dir/history.json" | wc -l)
grep -q '^{"pixel":\[160,100\],"truncated":false,"fragments":\[' "$dir/history.json" ||
  fail "the JSON does not start with the pixel: $(head -c 200 "$dir/history.json")"
((header > 1)) || fail "expected several fragments at (160, 100), the table says $header"
[[ $rows == "$header" ]] || fail "the table says $header fragments but has $rows rows"
[[ $json == "$header" ]] || fail "the table has $header fragments, the JSON $json"
# The JSON is valid (where a parser is at hand).
if command -v python3 >/dev/null; then
  n=$(python3 -c 'import json, sys; print(len(json.load(open(sys.argv[1]))["fragments"]))' "$dir/history.json")
  [[ $n == "$header" ]] || fail "the parsed JSON has $n fragments, the table $header"
fi

# --pixel outside the target: refused, naming the pixel and the size.
if "$raster" trace "${scene[@]}" --pixel 999,999 >"$dir/out.txt" 2>"$dir/err.txt"; then
  fail "--pixel 999,999 on a 320x180 target succeeded"
fi
grep -q '999,999' "$dir/err.txt" || fail "the message does not name the pixel: $(cat "$dir/err.txt")"
grep -q '320x180' "$dir/err.txt" || fail "the message does not name the target size: $(cat "$dir/err.txt")"

# --draw past the last draw: refused, naming the draw count.
if "$raster" trace "${scene[@]}" --draw 9 >"$dir/out.txt" 2>"$dir/err.txt"; then
  fail "--draw 9 of a two-draw frame succeeded"
fi
grep -q -- '--draw 9' "$dir/err.txt" || fail "the message does not name the draw: $(cat "$dir/err.txt")"
grep -q '2 draws' "$dir/err.txt" || fail "the message does not name the draw count: $(cat "$dir/err.txt")"

# --draw 1: the particle draw's geometry, counted in full, records limited by --limit.
"$raster" trace "${scene[@]}" --draw 1 --limit 3 >"$dir/draw.txt"
grep -q '^input assembler → vertex shader: 500 invocations$' "$dir/draw.txt" || fail "draw 1 lacks 500 VS invocations"
grep -q '^geometry shader output: 2000 vertices$' "$dir/draw.txt" || fail "draw 1 lacks 2000 GS vertices"
grep -q '^clip → setup: 500 primitives$' "$dir/draw.txt" || fail "draw 1 lacks 500 primitives"
[[ $(grep -c '^  prim [0-9]* rectangle' "$dir/draw.txt") == 3 ]] || fail "--limit 3 should list three primitives"
echo "trace CLI: $header fragments at (160, 100); errors name the pixel and the draw count"
