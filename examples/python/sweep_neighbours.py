#!/usr/bin/python3
"""A parameter sweep of ReSTIR DI's spatial neighbours: for each count, the relMSE of one real-time frame
(no accumulation, frame `--frames` of a still camera) against a converged reference, the frame time, and
their product (lower: better at equal time), as a table and a bar plot.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/sweep_neighbours.py --scene builtin:manylights
"""
import argparse
import statistics

import candela


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scene", default="builtin:manylights", help="builtin:NAME or a .gltf/.glb file")
    p.add_argument("--lights", type=int, default=1024, help="builtin:manylights' light count")
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--height", type=int, default=180)
    p.add_argument("--neighbours", default="0,1,2,5,8", help="counts to sweep, comma-separated")
    p.add_argument("--frames", type=int, default=8, help="frames rendered per count (the last is measured)")
    p.add_argument("--seeds", type=int, default=3, help="runs per count (their relMSE is averaged)")
    p.add_argument("--reference-spp", type=int, default=1024, help="samples per pixel of the reference")
    p.add_argument("--plot", default="sweep_neighbours.png", help="output PNG")
    return p.parse_args()


def main():
    args = parse_args()
    scene = candela.load_scene(args.scene, lights=args.lights)
    size = dict(width=args.width, height=args.height, jitter=False)
    reference = candela.Renderer(scene, method="direct", spp=args.reference_spp, sampler="independent",
                                 **size).render_frame().radiance.copy()
    rows = []
    for n in (int(k) for k in args.neighbours.split(",")):
        errors, times = [], []
        for seed in range(args.seeds):
            r = candela.Renderer(scene, method="restir-di", di_neighbours=n, accumulate=False, seed=seed + 1, **size)
            for _ in range(args.frames):
                frame = r.render_frame()
                times.append(frame.stats["total_ms"])
            errors.append(candela.metrics.rel_mse(frame.radiance, reference))
        rows.append((n, statistics.mean(errors), statistics.median(times)))
    print(f"{'neighbours':>10} {'relMSE':>10} {'frame ms':>9} {'relMSE x ms':>12}")
    for n, error, ms in rows:
        print(f"{n:10d} {error:10.4g} {ms:9.1f} {error * ms:12.4g}")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(8, 3.5))
    labels = [str(n) for n, _, _ in rows]
    left.bar(labels, [e for _, e, _ in rows])
    left.set_xlabel("spatial neighbours")
    left.set_ylabel(f"relMSE of frame {args.frames}")
    right.bar(labels, [e * ms for _, e, ms in rows])
    right.set_xlabel("spatial neighbours")
    right.set_ylabel("relMSE x frame ms")
    fig.suptitle(f"{args.scene}, {args.width}x{args.height}, restir-di")
    fig.tight_layout()
    fig.savefig(args.plot, dpi=100)
    print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
