#!/usr/bin/env bash
# Efficiency of one ReSTIR option's values, for choosing defaults by measurement: for each value, frame 16
# of a still camera (--no-jitter, 320x180) over SEEDS seeds, its relMSE against a converged reference and
# its estimator time (every stage but the G-buffer: scene_update counts, since the light tree's refit is part
# of it), and their product (lower is better: at equal time, relMSE scales as 1 / time for independent frames,
# so relMSE x time compares values at equal time). The reference takes the OTHER OPTIONS that change what the
# image converges to (--max-depth, --fps, --environment, ...): all of them but the light and random-number
# samplers, which it chooses itself, and the ReSTIR options (--di-*, --gi-*), which it does not read; its
# file name records them.
# usage: tools/sweep_restir.sh SCENE METHOD OPTION "VALUE..." [SEEDS [OTHER OPTIONS...]]    (writes into out/sweep/)
#   e.g. tools/sweep_restir.sh builtin:manylights restir-di --di-neighbours "1 2 5"
#        tools/sweep_restir.sh builtin:city restir-di --di-light-tile-size "64 256" 3 --light-sampler tree --di-light-tiles 1
set -euo pipefail
cd "$(dirname "$0")/.."
scene=$1; method=$2; option=$3; values=$4; seeds=${5:-3}
shift $(( $# < 5 ? $# : 5 )); others=("$@")
out=out/sweep; mkdir -p "$out"
name=$(basename "$scene" .gltf); name=${name#builtin:}
common=(--width 320 --height 180 --environment 0 --no-jitter -q)
if [ "$method" = restir-di ]; then
  reference=(--method direct --light-sampler tree)
else
  # GI: 3 bounces unless the other options name a depth.
  [[ " ${others[*]:-} " == *" --max-depth "* ]] || common+=(--max-depth 3)
  reference=(--method pt --light-sampler power)
fi
scene_options=()
for ((k = 0; k < ${#others[@]}; ++k)); do
  case ${others[k]} in
    --light-sampler | --sampler | --di-* | --gi-*)  # and the option's value, where one follows
      [[ $((k + 1)) -lt ${#others[@]} && ${others[k + 1]} != --* ]] && k=$((k + 1)) ;;
    *) scene_options+=("${others[k]}") ;;
  esac
done
ref="$out/${name}_${method}_reference.exr"
if [ ${#scene_options[@]} -gt 0 ]; then
  ref="$out/${name}_${method}_reference_$(printf '%s ' "${scene_options[@]}" | md5sum | cut -c1-8).exr"
fi
[ -f "$ref" ] || ./build/candela render "$scene" "${common[@]}" "${reference[@]}" ${scene_options[@]+"${scene_options[@]}"} \
  --spp 1024 --seed 99 --out "$ref"
printf "%-20s %-10s %-24s %10s %10s %12s  %s\n" scene method "$option" relMSE ms "relMSE x ms" "${others[*]:-}"
for value in $values; do
  python3 - "$scene" "$method" "$option" "$value" "$seeds" "$ref" "$out/$name" "${common[@]}" ${others[@]+"${others[@]}"} <<'EOF'
import json, subprocess, sys
scene, method, option, value, seeds, ref, prefix = sys.argv[1:8]
common = sys.argv[8:]
errors, times = [], []
for seed in range(1, int(seeds) + 1):
    image, stats = f"{prefix}_{method}_{value}_{seed}.exr", f"{prefix}_{method}_{value}_{seed}.json"
    subprocess.run(["./build/candela", "render", scene, *common, "--method", method, option, value, "--frames", "16",
                    "--no-accumulate", "--seed", str(seed), "--stats", stats, "--out", image], check=True)
    last = json.load(open(stats))[-1]
    times.append(sum(s["ms"] for s in last["stages"] if s["name"] != "gbuffer"))
    compare = subprocess.run(["./build/candela", "compare", image, ref], check=True, capture_output=True, text=True).stdout
    errors.append(float(compare.split("rel_mse")[1].split()[0]))
rel, ms = sum(errors) / len(errors), sorted(times)[len(times) // 2]
name = scene.split(":")[-1].split("/")[-1]
print(f"{name:20s} {method:10s} {option + ' ' + value:24s} {rel:10.4g} {ms:10.1f} {rel * ms:12.4g}")
EOF
done
