#!/usr/bin/env python3
"""Writes scenes/cornell-box.json from the measured Cornell box data.

Source of every number: Cornell University Program of Computer Graphics, "Cornell Box Data",
https://www.graphics.cornell.edu/online/box/data.html (geometry in mm, spectral reflectance of the
white, green and red paint at 4 nm steps 400-700 nm, the light's emission at 400/500/600/700 nm).
The CSV transcriptions used here live in ../shared/data of the development workspace; the generated
JSON is committed, so users never need this script.

The light quad lies in the ceiling plane; instead of lowering it we cut the matching hole in the
ceiling (the ceiling is an inline mesh around the light), so no two faces overlap.
"""
import csv
import json
import sys
from pathlib import Path


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def is_planar(quad, tolerance=1e-6):
    """Whether the quad's 4th vertex lies on the plane of the first three (relative to its size)."""
    a, b, c, d = quad
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    norm = sum(x * x for x in n) ** 0.5
    dist = abs(sum(n[i] * (d[i] - a[i]) for i in range(3))) / norm
    size = max(sum((p[i] - q[i]) ** 2 for i in range(3)) ** 0.5 for p in quad for q in quad)
    return dist <= tolerance * size


def main(data_dir, out_path):
    data = Path(data_dir)
    quads = {}
    for r in rows(data / "cornell_box_geometry.csv"):
        quads.setdefault(r["surface"], {"material": r["material"], "v": []})["v"].append(
            [float(r["x_mm"]), float(r["y_mm"]), float(r["z_mm"])])
    refl = rows(data / "cornell_box_reflectance.csv")
    light = rows(data / "cornell_box_light.csv")
    nm = [float(r["wavelength_nm"]) for r in refl]
    materials = {m: {"reflectance": {"nm": nm, "values": [float(r[m]) for r in refl]}}
                 for m in ("white", "green", "red")}
    surfaces = []
    for name, q in quads.items():
        if name == "ceiling":
            outer, hole = q["v"], quads["light"]["v"]
            # Pair each outer corner with the hole corner on the same side (same x/z extremes).
            hole_for = [min(hole, key=lambda h: abs(h[0] - o[0]) + abs(h[2] - o[2])) for o in outer]
            vertices = outer + hole_for
            triangles = []
            for k in range(4):
                a, b = k, (k + 1) % 4
                triangles += [[a, b, 4 + b], [a, 4 + b, 4 + a]]
            surfaces.append({"name": name, "material": "white",
                             "mesh": {"vertices": vertices, "triangles": triangles}})
        elif name == "light":
            surfaces.append({"name": name, "material": "white", "polygon": q["v"],
                             "emission": {"radiance": {"nm": [float(r["wavelength_nm"]) for r in light],
                                                       "values": [float(r["emission"]) for r in light]},
                                          "lobe": "lambert"}})
        elif is_planar(q["v"]):
            surfaces.append({"name": name, "material": q["material"], "polygon": q["v"]})
        else:
            # The measured walls are not exactly planar (the left wall by about 1.6 mm): keep the
            # data as two triangles rather than flatten it.
            surfaces.append({"name": name, "material": q["material"],
                             "mesh": {"vertices": q["v"], "triangles": [[0, 1, 2], [0, 2, 3]]}})
    scene = {
        "lambert": 1,
        "name": "cornell-box",
        "description": "The measured Cornell box (Cornell University Program of Computer Graphics, "
                       "https://www.graphics.cornell.edu/online/box/data.html): geometry in mm, measured "
                       "spectral reflectances, the light's measured relative emission used as spectral "
                       "radiance. The ceiling has a hole where the light is.",
        "units": "mm",
        "spectrum": {"mode": "spectral", "from_nm": 400, "to_nm": 700, "step_nm": 5},
        "materials": materials,
        "surfaces": surfaces,
        "probes": [{"name": "floor-grid", "normal": [0, 1, 0],
                    "grid": {"origin": [50, 1, 50], "u": [450, 0, 0], "v": [0, 0, 450], "nu": 9, "nv": 9}}],
        # 3 200 mm² patches, split further in the blocks' penumbrae and next to the probe points
        # (meshing.refine_direct, on by default): every surface and the probe grid within 1 % of the
        # converged answer in under 1 s (docs/BENCHMARKS.md).
        "meshing": {"max_patch_area": 3200},
    }
    Path(out_path).write_text(json.dumps(scene, indent=1) + "\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "../shared/data",
         sys.argv[2] if len(sys.argv) > 2 else "scenes/cornell-box.json")
