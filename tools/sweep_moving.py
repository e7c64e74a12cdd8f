#!/usr/bin/env python3
"""Efficiency of one render setting's values on a moving shot, for choosing defaults that only matter in motion
(disocclusion, history caps): tools/sweep_restir.sh's measure, but on the frames of a shot script.

For each value and seed, the shot's frames 0..LAST render without a denoiser and with pixel-centre rays
(`candela render --script`, the setting overridden in a copy of the script); at each evaluated frame the image's
relMSE is taken against a converged reference of the same frame (`direct` with the light tree, 1,024 spp, seed
99; for `restir`, `pt` with the power sampler), and the estimator time of every frame after the first (every stage
but the G-buffer: scene_update counts, since the light tree's refit is part of it). Prints the mean relMSE over evaluated frames and seeds (and its median: one firefly can rule
the mean), the median time and their product (lower is better at equal time). Seeds run in the outer loop, values
in the inner, so that the machine's drift falls on every value alike.

usage: tools/sweep_moving.py SHOT.json KEY "VALUE..." [--seeds N] [--last F] [--eval F,F,...] [--method M]
                             [--set KEY=VALUE ...]
  e.g. tools/sweep_moving.py docs/shots/orbit_manylights.json di_disocclusion_neighbours "3 10" --seeds 2
       tools/sweep_moving.py docs/shots/orbit_manylights.json gi_disocclusion_neighbours "6 10" --method restir \
           --set max_depth=3
--method replaces the shot's method; --set changes a key of the runs and of the reference alike.
KEY is a script key (settings.md's long option name with _ for -); values are JSON (3, true, "tree").
Writes into out/moving/.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

CANDELA = "./build/candela"


def write_script(base, overrides, images, stats, path):
    script = dict(base)
    script.update(overrides)
    script["history_reset_every"] = 0
    script["output"] = {"images": [images]}
    if stats:
        script["output"]["stats"] = stats
    with open(path, "w") as f:
        json.dump(script, f, indent=1)


def rel_mse(image, reference):
    out = subprocess.run([CANDELA, "compare", image, reference], check=True, capture_output=True, text=True).stdout
    return float(out.split("rel_mse")[1].split()[0])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("shot")
    parser.add_argument("key")
    parser.add_argument("values")
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--last", type=int, default=23, help="last frame rendered (from 0)")
    parser.add_argument("--eval", default="8,16,23", help="frames whose relMSE counts")
    parser.add_argument("--method", help="the method of the runs (default: the shot's)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="a key of runs and reference")
    args = parser.parse_args()
    base = json.load(open(args.shot))
    base.pop("denoise", None)
    # Pixel-centre primary rays in runs and reference alike, so that aliasing does not count (a jittered ray that
    # hits a tiny bright emitter is a "firefly" no estimator setting changes).
    base["jitter"] = False
    for setting in args.set:
        key, _, value = setting.partition("=")
        base[key] = json.loads(value)
    if args.method:
        base["method"] = args.method
    frames = [int(f) for f in args.eval.split(",")]
    if max(frames) > args.last:
        sys.exit(f"error: --eval frame {max(frames)} is after --last {args.last}")
    out = "out/moving"
    os.makedirs(out, exist_ok=True)
    method = base.get("method", "pt")
    name = "_".join([os.path.splitext(os.path.basename(args.shot))[0], method, "centre"] +
                    [s.replace("=", "") for s in args.set])
    # The reference of each evaluated frame: a method without history, so that each frame renders alone.
    reference = {"method": "direct", "light_sampler": "tree"} if method == "restir-di" else {
        "method": "pt", "light_sampler": "power"}
    reference.update(spp=1024, seed=99)
    ref_pattern = f"{out}/{name}_reference_%04d.exr"
    for f in frames:
        if os.path.exists(ref_pattern % f):
            continue
        path = f"{out}/{name}_reference.json"
        write_script(base, reference, ref_pattern, None, path)
        subprocess.run([CANDELA, "render", "--script", path, "--frames", f"{f}:{f}", "-q"], check=True)
    print(f"{'shot':24s} {args.key + ' value':36s} {'relMSE':>10s} {'median':>10s} {'ms':>8s} {'relMSE x ms':>12s}")
    # Seeds outside, values inside: the machine's drift over the run falls on every value alike.
    values = args.values.split()
    errors, times = {v: [] for v in values}, {v: [] for v in values}
    for seed in range(1, args.seeds + 1):
        for value in values:
            tag = f"{name}_{args.key}_{value}_{seed}"
            path, images, stats = f"{out}/{tag}.json", f"{out}/{tag}_%04d.exr", f"{out}/{tag}_stats"
            write_script(base, {args.key: json.loads(value), "seed": seed}, images, stats, path)
            for f in range(args.last + 1):  # an earlier sweep's frames would count as finished and not render
                if os.path.exists(images % f):
                    os.remove(images % f)
            subprocess.run([CANDELA, "render", "--script", path, "--frames", f"0:{args.last}", "-q"], check=True)
            for frame in json.load(open(f"{stats}_0-{args.last}.json"))[1:]:
                times[value].append(
                    sum(s["ms"] for s in frame["stages"] if s["name"] != "gbuffer"))
            errors[value] += [rel_mse(images % f, ref_pattern % f) for f in frames]
    for value in values:
        rel, ms = statistics.mean(errors[value]), statistics.median(times[value])
        median = statistics.median(errors[value])
        print(f"{name:24s} {args.key + ' ' + value:36s} {rel:10.4g} {median:10.4g} {ms:8.1f} {rel * ms:12.4g}",
              flush=True)


if __name__ == "__main__":
    main()
