#!/usr/bin/env bash
# Writes the fuzzers' seed corpus (never committed: generated here each time) into OUT_DIR:
#   exr/    a frame of the shipped sample in each EXR compression, half and float, small tiled,
#           mip-mapped and one-channel files, and a truncated frame (oiiotool, openimageio-tools);
#   crops/  crop-window documents as statfilter detect writes them, and broken ones;
#   cli/    command lines (arguments separated by NUL) like the README's.
# Usage: fuzz/make_seeds.sh OUT_DIR
set -euo pipefail
out="$1"
sample="${STATFILTER_SAMPLE:-$(cd "$(dirname "$0")/.." && pwd)/sample}"
mkdir -p "$out/exr" "$out/crops" "$out/cli"

frame="$sample/cornell_moving/spp0004/indirect.0001.exr"
# A 32 x 24 corner keeps each seed small, so that the fuzzer runs many inputs a second.
for compression in zip none rle zips piz pxr24 b44 dwaa; do
  oiiotool "$frame" --cut 32x24+64+48 -d half --compression "$compression" -o "$out/exr/sample_$compression.exr"
done
oiiotool "$frame" --cut 32x24+64+48 -d float -o "$out/exr/sample_float.exr"
head -c 2000 "$frame" > "$out/exr/truncated.exr"
oiiotool --create 8x6 4 -d half --tile 4 4 -o "$out/exr/tiled.exr"
oiiotool --create 16x16 3 -d float -otex "$out/exr/mipmap.exr"
oiiotool --create 5x3 1 --chnames Y -o "$out/exr/one_channel.exr"

cat > "$out/crops/detect.json" <<'JSON'
{
  "format": "statfilter-crops", "version": 1, "width": 160, "height": 120, "frame_count": 32,
  "padding": 4, "min_size": 8, "window_cost": 64, "flagged_pixels": 120, "window_count": 3,
  "frames": [
    {"frame": 1, "flagged_pixels": 40, "windows": [
      {"x": 10, "y": 12, "width": 30, "height": 20, "border": [0.0625, 0.7333, 0.25, 0.9]},
      {"x": 100, "y": 90, "width": 60, "height": 30, "border": [0.625, 0.0, 1.0, 0.25]}]},
    {"frame": 7, "flagged_pixels": 80, "windows": [{"x": 0, "y": 0, "width": 160, "height": 120, "border": [0, 0, 1, 1]}]}
  ]
}
JSON
printf '{"format": "statfilter-crops", "version": 1, "width": 4, "height": 4, "frames": []}' > "$out/crops/empty.json"
printf '{"format": "statfilter-crops", "version": 1, "width": 1e300, "height": -1, "frames": [{"frame": -9007199254740993, "windows": [{"x": 1, "y": 2, "width": 3, "height": 4}]}]}' > "$out/crops/extremes.json"
printf '{"format": "statfilter-crops", "version": 1, "width": 160,' > "$out/crops/truncated.json"
printf '[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[["\\u12' > "$out/crops/nested.json"

seed() { local name="$1"; shift; printf '%s\0' "$@" | head -c -1 > "$out/cli/$name"; }
seed info info 'shot/indirect.####.exr' --json --frames 1-10,12-20
seed denoise denoise 'in.####.exr' 'out.####.exr' --method error-threshold --window 9 --threshold 2
seed channels denoise 'frame.%04d.exr' 'ind.@@@.exr' --channels 'ViewLayer.Diffuse Indirect' --float
seed merge merge 'den.####.exr' 'rr.{window}.####.exr' 'final.####.exr' --crops crops.json --feather=1
seed frames copy 'a.#.exr' 'b.%040d.exr' --frames 1-100x3,-5--2 -q
seed bad info --frames '' -x --=
