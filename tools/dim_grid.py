#!/usr/bin/env python3
"""Turn off the emission of most cells of a gridded glTF scene (from ../shared/scenes/tools/make_manylight.py
--grid), keeping the geometry: the same scene with a fraction of its lights, for comparing frame costs at
equal geometry (docs/performance.md, "Setup of a million-light scene").

usage: tools/dim_grid.py GRID.gltf OUT.gltf [--keep FRACTION]   (default 0.01: one cell in a hundred emits)

The output is written next to the input and shares its .bin and images. Meshes of dimmed cells point to
copies whose materials have no emission (emissiveFactor and emissiveTexture removed).
"""
import argparse
import copy
import json
import os
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("grid")
    ap.add_argument("out")
    ap.add_argument("--keep", type=float, default=0.01, help="fraction of grid cells that keep their emission")
    a = ap.parse_args()
    if os.path.dirname(os.path.abspath(a.out)) != os.path.dirname(os.path.abspath(a.grid)):
        sys.exit(f"{a.out}: must be in the directory of {a.grid} (it shares its buffers and images)")
    with open(a.grid) as f:
        g = json.load(f)
    cells = [n for n in g["scenes"][g.get("scene", 0)]["nodes"] if g["nodes"][n].get("name", "").startswith("grid_")]
    if not cells:
        sys.exit(f"{a.grid}: no grid_* nodes at the scene's root (make it with make_manylight.py --grid)")
    keep = max(1, round(len(cells) * a.keep))

    dark_material = {}
    for i, m in enumerate(list(g.get("materials", []))):
        d = copy.deepcopy(m)
        d.pop("emissiveFactor", None)
        d.pop("emissiveTexture", None)
        d.get("extensions", {}).pop("KHR_materials_emissive_strength", None)
        d["name"] = m.get("name", f"material{i}") + "_dark"
        dark_material[i] = len(g["materials"])
        g["materials"].append(d)
    dark_mesh = {}

    def dark(mesh):
        if mesh not in dark_mesh:
            d = copy.deepcopy(g["meshes"][mesh])
            for p in d["primitives"]:
                if "material" in p:
                    p["material"] = dark_material[p["material"]]
            dark_mesh[mesh] = len(g["meshes"])
            g["meshes"].append(d)
        return dark_mesh[mesh]

    def dim(node):
        n = g["nodes"][node]
        if "mesh" in n:
            n["mesh"] = dark(n["mesh"])
        for c in n.get("children", []):
            dim(c)

    for cell in cells[keep:]:
        dim(cell)
    with open(a.out, "w") as f:
        json.dump(g, f)
    print(f"wrote {a.out}: {keep} of {len(cells)} grid cells emit")


if __name__ == "__main__":
    main()
