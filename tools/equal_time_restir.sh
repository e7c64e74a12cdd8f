#!/usr/bin/env bash
# Equal-time comparison of ReSTIR DI against the light-tree `direct` estimator: ReSTIR DI renders 16 frames
# of a still camera; its last frame's estimator time (all stages after the G-buffer) becomes the time
# budget of one frame of `direct`. Both images are compared with a converged reference (1024 spp of
# `direct`, another seed). Primary rays go through pixel centres (--no-jitter) in all three renders, so
# the error measured is the light transport estimator's, not aliasing.
# usage: tools/equal_time_restir.sh SCENE [LIGHT_SAMPLER] [REFERENCE_SPP]    (writes into out/equal_time/)
set -euo pipefail
cd "$(dirname "$0")/.."
scene=$1; sampler=${2:-power}; ref_spp=${3:-1024}
out=out/equal_time; mkdir -p "$out"
name=$(basename "$scene" .gltf); name=${name#builtin:}
common=(--width 320 --height 180 --environment 0 --no-jitter -q)
ref="$out/${name}_reference_nojitter.exr"
[ -f "$ref" ] || ./build/candela render "$scene" "${common[@]}" --method direct --light-sampler tree --spp "$ref_spp" --seed 99 --out "$ref"
restir="$out/${name}_restir_di.exr"
./build/candela render "$scene" "${common[@]}" --method restir-di --light-sampler "$sampler" --frames 16 --no-accumulate \
  --stats "$out/${name}_restir_di.json" --out "$restir"
budget=$(python3 -c "
import json, sys
last = json.load(open(sys.argv[1]))[-1]
print(sum(s['ms'] for s in last['stages'] if s['name'] not in ('scene_update', 'gbuffer')))" "$out/${name}_restir_di.json")
direct="$out/${name}_direct_tree.exr"
./build/candela render "$scene" "${common[@]}" --method direct --light-sampler tree --time-budget-ms "$budget" \
  --stats "$out/${name}_direct_tree.json" --out "$direct"
spp=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[0]['spp'])" "$out/${name}_direct_tree.json")
rel_restir=$(./build/candela compare "$restir" "$ref" | sed 's/.*rel_mse \([^ ]*\).*/\1/')
rel_direct=$(./build/candela compare "$direct" "$ref" | sed 's/.*rel_mse \([^ ]*\).*/\1/')
printf "%-18s budget %.1f ms | restir-di (%s, frame 16) relMSE %s | direct tree %s spp relMSE %s | ratio %.3f\n" \
  "$name" "$budget" "$sampler" "$rel_restir" "$spp" "$rel_direct" "$(python3 -c "print($rel_restir / $rel_direct)")"
