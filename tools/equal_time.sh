#!/usr/bin/env bash
# Equal-time comparison of light selection for direct lighting: each sampler renders for the same time
# budget, then its relMSE against a converged reference (1024 spp, light tree, another seed) is measured.
# usage: tools/equal_time.sh SCENE [BUDGET_MS] [REFERENCE_SPP]    (writes into out/equal_time/)
set -euo pipefail
cd "$(dirname "$0")/.."
scene=$1; budget=${2:-2000}; ref_spp=${3:-1024}
out=out/equal_time; mkdir -p "$out"
name=$(basename "$scene" .gltf); name=${name#builtin:}
common=(--method direct --width 320 --height 180 --environment 0 -q)
ref="$out/${name}_reference.exr"
[ -f "$ref" ] || ./build/candela render "$scene" "${common[@]}" --light-sampler tree --spp "$ref_spp" --seed 99 --out "$ref"
printf "%-18s %-8s %6s %12s\n" scene sampler spp relMSE
for sampler in uniform power tree; do
  img="$out/${name}_${sampler}.exr"
  ./build/candela render "$scene" "${common[@]}" --light-sampler "$sampler" --time-budget-ms "$budget" \
    --stats "$out/${name}_${sampler}.json" --out "$img"
  spp=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[0]['spp'])" "$out/${name}_${sampler}.json")
  rel=$(./build/candela compare "$img" "$ref" | sed 's/.*rel_mse \([^ ]*\).*/\1/')
  printf "%-18s %-8s %6s %12s\n" "$name" "$sampler" "$spp" "$rel"
done
