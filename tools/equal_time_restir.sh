#!/usr/bin/env bash
# Equal-time comparison of ReSTIR against the estimator it replaces, on a still camera:
#   restir-di  vs  `direct` with the light tree (direct light only)
#   restir     vs  `pt` (plain path tracing, power light selection), paths of at most 3 bounces
# ReSTIR renders 16 frames; the median estimator time (all stages after the G-buffer) of frames 9-16 becomes
# the time budget of one frame of the other estimator (the last frame's alone moved by 20% between runs, enough to
# give the other estimator a second sample per pixel or not). Both images are compared with a converged reference
# (1024 spp of that estimator, another seed). Primary rays go through pixel centres (--no-jitter) in all
# renders, so the error measured is the light transport estimator's, not aliasing.
# usage: tools/equal_time_restir.sh SCENE [restir-di|restir] [REFERENCE_SPP] [RESTIR OPTIONS...]
#   (writes into out/equal_time/; options after the third argument go to the ReSTIR render alone, e.g.
#   --di-shaded-samples 2)
set -euo pipefail
cd "$(dirname "$0")/.."
scene=$1; method=${2:-restir-di}; ref_spp=${3:-1024}; shift $(( $# < 3 ? $# : 3 )); restir_options=("$@")
out=out/equal_time; mkdir -p "$out"
# The median estimator time (all stages after the G-buffer) of a --stats file's frames from index FIRST on.
median_estimator_ms() {
  python3 -c "
import json, statistics, sys
frames = json.load(open(sys.argv[1]))[int(sys.argv[2]):]
print(statistics.median(sum(s['ms'] for s in f['stages'] if s['name'] not in ('scene_update', 'gbuffer'))
                        for f in frames))" "$1" "$2"
}
# An image's relMSE against the reference ($ref, set below).
rel_mse() { ./build/candela compare "$1" "$ref" | sed 's/.*rel_mse \([^ ]*\).*/\1/'; }
name=$(basename "$scene" .gltf); name=${name#builtin:}
common=(--width 320 --height 180 --environment 0 --no-jitter -q)
if [ "$method" = restir-di ]; then
  other=(--method direct --light-sampler tree); other_name="direct tree"
else
  common+=(--max-depth 3); other=(--method pt --light-sampler power); other_name="pt"
fi
ref="$out/${name}_${method}_reference.exr"
[ -f "$ref" ] || ./build/candela render "$scene" "${common[@]}" "${other[@]}" --spp "$ref_spp" --seed 99 --out "$ref"
restir="$out/${name}_${method}.exr"
./build/candela render "$scene" "${common[@]}" --method "$method" "${restir_options[@]}" --frames 16 --no-accumulate \
  --stats "$out/${name}_${method}.json" --out "$restir"
budget=$(median_estimator_ms "$out/${name}_${method}.json" 8)
plain="$out/${name}_${method}_equal_time.exr"
./build/candela render "$scene" "${common[@]}" "${other[@]}" --time-budget-ms "$budget" \
  --stats "$out/${name}_${method}_equal_time.json" --out "$plain"
spp=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[0]['spp'])" "$out/${name}_${method}_equal_time.json")
rel_restir=$(rel_mse "$restir")
rel_plain=$(rel_mse "$plain")
printf "%-18s budget %.1f ms | %s (frame 16) relMSE %s | %s %s spp relMSE %s | ratio %.3f\n" \
  "$name" "$budget" "$method" "$rel_restir" "$other_name" "$spp" "$rel_plain" "$(python3 -c "print($rel_restir / $rel_plain)")"
# The other estimator renders whole samples per pixel (at least one), so the ratio above jumps where the budget
# crosses a multiple of its sample's time. Its error at exactly the budget, from variance x time being constant for
# an average of independent samples: the error of one sample per pixel (its equal-time render's error times its
# samples per pixel: the same instant as the reference, where the scene moves) and the warm time of one sample per
# pixel (the median estimator time of frames 3-6 of a 1-spp run), scaled by that time over the budget.
times="$out/${name}_${method}_one_spp.json"
./build/candela render "$scene" "${common[@]}" "${other[@]}" --spp 1 --frames 6 --no-accumulate --stats "$times" \
  --out "$out/${name}_${method}_one_spp.exr"
one_ms=$(median_estimator_ms "$times" 2)
rel_one=$(python3 -c "print($rel_plain * $spp)")
printf "%-18s %s 1 spp: %.1f ms, relMSE %.4g; at the budget by variance x time %.4g | ratio %.3f\n" \
  "$name" "$other_name" "$one_ms" "$rel_one" "$(python3 -c "print($rel_one * $one_ms / $budget)")" \
  "$(python3 -c "print($rel_restir / ($rel_one * $one_ms / $budget))")"
