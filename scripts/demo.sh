#!/usr/bin/env bash
# The main job on the sample that ships with statfilter: inspect the noisy 4-spp render, denoise it
# at the default quality (balanced: the method measured best for the scene's motion at its cost),
# and score input and output against the 1024-spp reference.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh build >/dev/null

statfilter=build/tools/statfilter
noisy="sample/cornell_moving/spp0004/indirect.####.exr"
reference="sample/cornell_moving/ref/indirect.####.exr"
mkdir -p out/demo

echo "== the noisy input"
"$statfilter" info "$noisy" --quiet
echo
echo "== denoise: --quality balanced (the default), which says what it picked and why"
"$statfilter" denoise "$noisy" out/demo/denoised.####.exr --quality balanced --quiet --json \
  | tee out/demo/denoise.json
echo
echo "== error against the reference (input, then output)"
"$statfilter" compare "$noisy" "$reference" --quiet | tee out/demo/input_error.txt
echo
"$statfilter" compare out/demo/denoised.####.exr "$reference" --quiet | tee out/demo/output_error.txt
before=$(awk '$1 == "rel_mse" {print $2}' out/demo/input_error.txt)
after=$(awk '$1 == "rel_mse" {print $2}' out/demo/output_error.txt)
seconds=$(grep -o '"seconds": [0-9.e-]*' out/demo/denoise.json | awk '{print $2}')
echo
printf "relMSE %.4f -> %.4f (%.1fx lower) in %.2f s; frames in out/demo/\n" "$before" "$after" \
  "$(echo "$before $after" | awk '{print $1 / $2}')" "$seconds"
