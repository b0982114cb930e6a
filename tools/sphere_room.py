#!/usr/bin/env python3
"""Writes the faceted-sphere rooms of docs/BENCHMARKS.md ("Faceted objects").

A closed 6 x 4 x 3 m room (faces inward) with NX x NY floating spheres, each an icosahedron whose faces
are split 1:4 LEVEL times (20 * 4^LEVEL triangles, every one in a plane of its own, so no planar region
can be joined and every input triangle is a root of the hierarchy). Every surface reflects 0.5.

  furnace: every surface emits 1 W/m^2/nm at one wavelength, so B = M / (1 - rho) = 2 on every patch
           (the spheres at mid-height, 1.5 m).
  lit:     nothing emits but a black 1 m^2 panel 1 mm under the ceiling's centre (100 W/m^2/nm), the
           spheres at 1.2 m; compare with the same scene solved by the dense solver (--method dense).

usage: tools/sphere_room.py OUT.json LEVEL NX NY [--lit] [--method hierarchical|dense]
                            [--accuracy A] [--max-patch-area A]
  (3 4 3 gives the 15 372-triangle furnace, 2 3 2 --lit --max-patch-area 0.05 the lit room)
"""
import argparse
import json
import math

from cube_room_furnace import box

ICOSAHEDRON_FACES = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
                     (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
                     (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]


def unit(p):
    n = math.sqrt(sum(x * x for x in p))
    return tuple(x / n for x in p)


def icosphere(level, centre, radius):
    """Vertices and triangles (counter-clockwise seen from outside) of a subdivided icosahedron."""
    t = (1 + math.sqrt(5)) / 2
    vertices = [unit(p) for p in [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                                  (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    faces = list(ICOSAHEDRON_FACES)
    for _ in range(level):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                vertices.append(unit(tuple((vertices[a][i] + vertices[b][i]) / 2 for i in range(3))))
                middle[key] = len(vertices) - 1
            return middle[key]

        finer = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            finer += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = finer
    return {"vertices": [[centre[i] + radius * p[i] for i in range(3)] for p in vertices],
            "triangles": [list(f) for f in faces]}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    parser.add_argument("level", type=int)
    parser.add_argument("nx", type=int)
    parser.add_argument("ny", type=int)
    parser.add_argument("--lit", action="store_true")
    parser.add_argument("--method", default="hierarchical", choices=["hierarchical", "dense"])
    parser.add_argument("--accuracy", type=float)
    parser.add_argument("--max-patch-area", type=float)
    args = parser.parse_args()
    emission = None if args.lit else {"exitance": 1.0}
    room = {"name": "room", "material": "grey", "mesh": box((0, 0, 0), (6, 4, 3), True)}
    surfaces = [dict(room, emission=emission) if emission else room]
    if args.lit:
        panel = [[2.5, 1.5, 2.999], [3.5, 1.5, 2.999], [3.5, 2.5, 2.999], [2.5, 2.5, 2.999]]
        surfaces.append({"name": "panel", "material": "black",
                         "mesh": {"vertices": panel, "triangles": [[0, 2, 1], [0, 3, 2]]},
                         "emission": {"exitance": 100.0}})
    radius = 0.35 * min(6 / args.nx, 4 / args.ny)
    height = 1.2 if args.lit else 1.5
    for i in range(args.nx):
        for j in range(args.ny):
            sphere = {"name": f"sphere {i} {j}", "material": "grey",
                      "mesh": icosphere(args.level, ((i + 0.5) * 6 / args.nx, (j + 0.5) * 4 / args.ny, height), radius)}
            if emission:
                sphere["emission"] = emission
            surfaces.append(sphere)
    solver = {"method": args.method}
    if args.accuracy is not None:
        solver["accuracy"] = args.accuracy
    scene = {
        "lambert": 1,
        "name": "sphere-room-lit" if args.lit else "sphere-room-furnace",
        "description": f"6 x 4 x 3 m room with {args.nx * args.ny} floating faceted spheres "
                       f"({20 * 4 ** args.level} triangles each), rho = 0.5"
                       + (", lit by a 1 m^2 ceiling panel." if args.lit else ", M = 1 everywhere: B = 2 exactly."),
        "spectrum": {"mode": "spectral", "wavelengths_nm": [555]},
        "materials": {"grey": {"reflectance": 0.5}, "black": {"reflectance": 0.0}},
        "surfaces": surfaces,
        "solver": solver,
    }
    if args.max_patch_area is not None:
        scene["meshing"] = {"max_patch_area": args.max_patch_area}
    with open(args.out, "w") as f:
        json.dump(scene, f)
    print(sum(len(s["mesh"]["triangles"]) for s in surfaces), "input triangles")


if __name__ == "__main__":
    main()
