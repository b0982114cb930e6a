#!/usr/bin/env python3
"""Writes the cube-room furnace of docs/BENCHMARKS.md ("Furnace: 6 x 4 x 3 m room with a floating 1 m cube").

A closed 6 x 4 x 3 m room (faces inward) with a floating 1 m cube at its centre (faces outward, 1 m
above the floor). Every surface reflects 0.5 and emits 1 W/m^2/nm at one wavelength, so the exact
radiosity is B = M / (1 - rho) = 2 on every patch. Solved by the hierarchical method.

usage: tools/cube_room_furnace.py OUT.json MAX_PATCH_AREA   (0.04 gives 4 544 patches, 0.01 18 176)
"""
import argparse
import json


def box(lo, hi, inward):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    # Each face's corners in the order that makes (b - a) x (c - a) point into the box.
    faces = [((x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)),
             ((x0, y0, z1), (x0, y1, z1), (x1, y1, z1), (x1, y0, z1)),
             ((x0, y0, z0), (x0, y0, z1), (x1, y0, z1), (x1, y0, z0)),
             ((x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)),
             ((x0, y0, z0), (x0, y1, z0), (x0, y1, z1), (x0, y0, z1)),
             ((x1, y0, z0), (x1, y0, z1), (x1, y1, z1), (x1, y1, z0))]
    vertices, triangles = [], []
    for face in faces:
        i = len(vertices)
        vertices.extend(list(p) for p in face)
        if inward:
            triangles.extend([[i, i + 1, i + 2], [i, i + 2, i + 3]])
        else:
            triangles.extend([[i, i + 2, i + 1], [i, i + 3, i + 2]])
    return {"vertices": vertices, "triangles": triangles}


def scene(max_patch_area):
    """The furnace scene (hierarchical method) at the given patch size."""
    return {
        "lambert": 1,
        "name": "cube-room-furnace",
        "description": "6 x 4 x 3 m room with a floating 1 m cube, rho = 0.5 and M = 1 everywhere: B = 2 exactly.",
        "spectrum": {"mode": "spectral", "wavelengths_nm": [555]},
        "materials": {"grey": {"reflectance": 0.5}},
        "surfaces": [
            {"name": "room", "material": "grey", "mesh": box((0, 0, 0), (6, 4, 3), True), "emission": {"exitance": 1.0}},
            {"name": "cube", "material": "grey", "mesh": box((2.5, 1.5, 1), (3.5, 2.5, 2), False),
             "emission": {"exitance": 1.0}},
        ],
        "meshing": {"max_patch_area": max_patch_area},
        "solver": {"method": "hierarchical"},
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    parser.add_argument("max_patch_area", type=float)
    args = parser.parse_args()
    with open(args.out, "w") as f:
        json.dump(scene(args.max_patch_area), f)


if __name__ == "__main__":
    main()
