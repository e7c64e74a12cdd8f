#!/usr/bin/env bash
# The time-to-error study of docs/convergence.md ("Time to error"): every `candela converge` method on one scene,
# direct-light methods against a direct-light reference and full-transport methods against a path-traced
# one, each reference rendered once with Sobol numbers and another seed (cached in out/time_to_error/).
# usage: tools/time_to_error.sh SCENE WIDTH HEIGHT direct|full [REFERENCE_SPP] [MAX_SECONDS]
# prints the converge table and the time to relMSE 0.05, 0.01 and 0.002 per method; writes
# out/time_to_error/NAME_WxH_KIND.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=$1; w=$2; h=$3; kind=$4; ref_spp=${5:-1024}; max_seconds=${6:-20}
out=out/time_to_error; mkdir -p "$out"
name=$(basename "$scene" .gltf); name=${name#builtin:}
ref="$out/${name}_${w}x${h}_${kind}_reference.exr"
csv="$out/${name}_${w}x${h}_${kind}.csv"
if [ "$kind" = direct ]; then
  methods=direct-uniform,direct-power,direct-tree,direct-uniform-sobol,direct-power-sobol,direct-tree-sobol
  methods+=,direct-tree-sobol+bilateral,direct-tree-sobol+svgf,restir-di-none,restir-di-basic,restir-di-pairwise
  methods+=,restir-di-pairwise+bilateral,restir-di-pairwise+svgf
  [ -f "$ref" ] || ./build/candela render "$scene" --method direct --light-sampler tree --sampler sobol --seed 8000 \
    --spp "$ref_spp" --no-jitter --width "$w" --height "$h" --out "$ref" -q
  given=(--reference-direct "$ref")
else
  methods=pt,pt-sobol,pt-sobol+bilateral,pt-sobol+svgf,restir,restir+bilateral,restir+svgf
  [ -f "$ref" ] || ./build/candela render "$scene" --method pt --light-sampler tree --sampler sobol --seed 8001 \
    --spp "$ref_spp" --no-jitter --width "$w" --height "$h" --out "$ref" -q
  given=(--reference "$ref")
fi
./build/candela converge "$scene" --width "$w" --height "$h" --max-spp 128 --max-seconds "$max_seconds" \
  "${given[@]}" --methods "$methods" --csv "$csv"
python3 - "$csv" <<'EOF'
import csv, math, sys
runs = {}
for r in csv.DictReader(open(sys.argv[1])):
    runs.setdefault(r["method"], []).append((int(r["samples"]), float(r["time_ms"]), float(r["rel_mse"])))
def time_to(points, target):  # as time_to_error in apps/converge.cpp
    for i, (n, t, e) in enumerate(points):
        if e <= target:
            if i == 0:
                return t
            _, t0, e0 = points[i - 1]
            f = math.log(target / e0) / math.log(e / e0)
            return math.exp(math.log(t0) + f * (math.log(t) - math.log(t0)))
    return None
targets = (0.05, 0.01, 0.002)
print("| method | ms per frame | " + " | ".join("to relMSE %g" % t for t in targets) + " |")
print("|---|---|" + "---|" * len(targets))
for method, points in runs.items():
    cells = []
    for t in targets:
        s = time_to(points, t)
        cells.append("%.2f s" % (s / 1000) if s is not None else "not reached (%d frames)" % points[-1][0])
    print("| `%s` | %.0f | %s |" % (method, points[-1][1] / points[-1][0], " | ".join(cells)))
EOF
