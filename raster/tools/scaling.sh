#!/usr/bin/env bash
# Prints the scaling tables of docs/PERFORMANCE.md: raster bench's time per frame against particle
# count and against resolution, with pixel-shader invocations, time per invocation and peak memory.
# Run from the project root after the README's build, on an otherwise idle machine:
#   bash raster/tools/scaling.sh [frames]
set -euo pipefail
raster=${RASTER:-build/bin/raster}
frames=${1:-5}

row() {  # label, then bench arguments
  local label=$1
  shift
  local out
  out=$("$raster" bench "$@" --frames "$frames" --no-error)
  local ms inv rss
  ms=$(sed -n 's/.*ms_per_frame_median=\([0-9.]*\).*/\1/p' <<<"$out")
  inv=$(sed -n 's/.*ps_invocations_per_frame=\([0-9]*\).*/\1/p' <<<"$out")
  rss=$(sed -n 's/.*peak_rss_mb=\([0-9.]*\).*/\1/p' <<<"$out")
  awk -v l="$label" -v ms="$ms" -v inv="$inv" -v rss="$rss" \
    'BEGIN { printf "| %s | %.2f | %.2f M | %.2f | %.0f |\n", l, ms, inv / 1e6, (inv > 0 ? ms * 1e6 / inv : 0), rss }'
}

echo "### particles, 1280×720, against count"
echo "| particles | ms/frame | PS invocations | ns/invocation | peak MB |"
echo "|---|---|---|---|---|"
for n in 1000 10000 100000 1000000; do row "$n" particles --count "$n"; done
echo
echo "### particles, 10 000, against resolution"
echo "| resolution | ms/frame | PS invocations | ns/invocation | peak MB |"
echo "|---|---|---|---|---|"
for r in 640x360 1280x720 1920x1080 3840x2160; do row "$r" particles --width "${r%x*}" --height "${r#*x}"; done
echo
echo "### fog (height, 16×16 cubes), against resolution"
echo "| resolution | ms/frame | PS invocations | ns/invocation | peak MB |"
echo "|---|---|---|---|---|"
for r in 640x360 1280x720 1920x1080 3840x2160; do row "$r" fog --width "${r%x*}" --height "${r#*x}"; done
