#!/usr/bin/python3
"""Equal-time comparison of light samplers: direct light accumulated frame after frame with each sampler,
its relMSE against a converged reference plotted against render time (log-log), and the time each sampler
needs to reach the error the slowest one ends at.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/equal_time_samplers.py --scene builtin:manylights
"""
import argparse
import time

import candela


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scene", default="builtin:manylights", help="builtin:NAME or a .gltf/.glb file")
    p.add_argument("--lights", type=int, default=1024, help="builtin:manylights' light count")
    p.add_argument("--width", type=int, default=256)
    p.add_argument("--height", type=int, default=144)
    p.add_argument("--samplers", default="power,tree", help="light samplers to compare, comma-separated")
    p.add_argument("--seconds", type=float, default=4.0, help="render time per sampler")
    p.add_argument("--reference-spp", type=int, default=1024, help="samples per pixel of the reference")
    p.add_argument("--plot", default="equal_time_samplers.png", help="output PNG")
    return p.parse_args()


def curve(scene, sampler, reference, seconds, common):
    """(render seconds, relMSE) after each accumulated frame, until `seconds` of rendering."""
    r = candela.Renderer(scene, light_sampler=sampler, **common)
    points, rendering = [], 0.0
    while rendering < seconds:
        start = time.perf_counter()
        frame = r.render_frame()
        rendering += time.perf_counter() - start
        points.append((rendering, candela.metrics.rel_mse(frame.radiance, reference)))
    return points


def time_to(points, error):
    """The render time at which the error first reaches `error` (None: never)."""
    return next((t for t, e in points if e <= error), None)


def main():
    args = parse_args()
    scene = candela.load_scene(args.scene, lights=args.lights)
    common = dict(width=args.width, height=args.height, method="direct", jitter=False)
    reference = candela.Renderer(scene, spp=args.reference_spp, light_sampler="power", sampler="independent",
                                 **common).render_frame().radiance.copy()
    curves = {s: curve(scene, s, reference, args.seconds, common) for s in args.samplers.split(",")}
    target = max(points[-1][1] for points in curves.values())
    print(f"{'sampler':10} {'frames':>6} {'final relMSE':>12} {'s to relMSE %.4g' % target:>18}")
    for sampler, points in curves.items():
        print(f"{sampler:10} {len(points):6d} {points[-1][1]:12.4g} {time_to(points, target):18.3f}")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for sampler, points in curves.items():
        ax.loglog([t for t, _ in points], [e for _, e in points], marker=".", label=sampler)
    ax.set_xlabel("render time (s)")
    ax.set_ylabel("relMSE")
    ax.set_title(f"{args.scene}, {args.width}x{args.height}, direct light")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.plot, dpi=100)
    print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
