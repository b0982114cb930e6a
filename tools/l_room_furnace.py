#!/usr/bin/env python3
"""Writes an L-shaped furnace room with the hard cases of issue 4's acceptance scenes, or checks a result.

The room: an L-shaped floor plan (6 x 4 m less a 2 x 2 m corner), 3 m high, faces inward, its floor
made of 40 strips 0.1 m wide (up to 6 m long: triangles of aspect 120, joined again by the solver's
sliver merge). In it: a floating cube, a crate without a bottom standing on the floor (the floor
under it is enclosed), and a plate 1 cm thick. Every surface reflects RHO and emits 1 W/m^2/nm at one
wavelength, so the exact radiosity of every patch that sees the room is B = 1 / (1 - RHO).

usage:
  tools/l_room_furnace.py OUT.json [--rho R] [--scale S] [--offset X Y Z] [--method M] [--max-patch-area A]
  tools/l_room_furnace.py --check RESULT.json --rho R     prints max |B (1 - R) - 1| and exits 1 above 1e-3

--scale multiplies every coordinate (and the patch area by its square); --offset is then added
(e.g. 512345.678 5523456.789 100 for geo-referenced coordinates).
"""
import argparse
import json
import sys

from city_block import quad
from cube_room_furnace import box

H = 3.0
L_PLAN = [(0, 0), (6, 0), (6, 2), (4, 2), (4, 4), (0, 4)]  # counter-clockwise seen from above


def l_room():
    vertices, triangles = [], []
    for k in range(40):  # floor strips, facing up
        y0, y1 = k * 0.1, (k + 1) * 0.1
        x1 = 6 if y1 <= 2 + 1e-9 else 4
        quad(vertices, triangles, (0, y0, 0), (x1, y0, 0), (x1, y1, 0), (0, y1, 0))
    for x0, y0, x1, y1 in [(0, 0, 4, 2), (4, 0, 6, 2), (0, 2, 4, 4)]:  # ceiling, facing down
        quad(vertices, triangles, (x0, y0, H), (x0, y1, H), (x1, y1, H), (x1, y0, H))
    for k, (px, py) in enumerate(L_PLAN):  # walls, facing into the plan
        qx, qy = L_PLAN[(k + 1) % len(L_PLAN)]
        quad(vertices, triangles, (px, py, 0), (px, py, H), (qx, qy, H), (qx, qy, 0))
    return {"vertices": vertices, "triangles": triangles}


def crate():
    mesh = box((2.2, 0.5, 0), (3.0, 1.3, 0.9), False)
    # No bottom (box's first face, vertices 0-3): it stands on the floor.
    return {"vertices": mesh["vertices"][4:], "triangles": [[i - 4 for i in t] for t in mesh["triangles"][2:]]}


def transform(mesh, scale, offset):
    return {"vertices": [[scale * p[k] + offset[k] for k in range(3)] for p in mesh["vertices"]],
            "triangles": mesh["triangles"]}


def write(args):
    parts = {"room": l_room(), "cube": box((1, 2.6, 1.2), (1.8, 3.4, 2.0), False), "crate": crate(),
             "plate": box((4.5, 0.5, 1.0), (5.5, 1.5, 1.01), False)}
    scene = {
        "lambert": 1,
        "name": "l-room-furnace",
        "description": f"L-shaped furnace room with strips, a floating cube, a bottomless crate and a 1 cm plate; "
                       f"rho = {args.rho}, M = 1: B = 1/(1 - rho) = {1 / (1 - args.rho):.9g} on every open patch.",
        "spectrum": {"mode": "spectral", "wavelengths_nm": [555]},
        "materials": {"grey": {"reflectance": args.rho}},
        "surfaces": [{"name": name, "material": "grey", "mesh": transform(mesh, args.scale, args.offset),
                      "emission": {"exitance": 1.0}} for name, mesh in parts.items()],
        "meshing": {"max_patch_area": args.max_patch_area * args.scale ** 2},
        "solver": {"method": args.method},
    }
    with open(args.out, "w") as f:
        json.dump(scene, f)


def check(args):
    with open(args.check) as f:
        result = json.load(f)
    worst = max(abs(B * (1 - args.rho) - 1) for p in result["patches"] for B in p["radiosity"])
    print(f"{len(result['patches'])} patches, max |B (1 - rho) - 1| = {worst:.3g}")
    return 0 if worst <= 1e-3 else 1


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", nargs="?")
    parser.add_argument("--rho", type=float, default=0.999)
    parser.add_argument("--scale", type=float, default=1.0)
    parser.add_argument("--offset", type=float, nargs=3, default=[0.0, 0.0, 0.0])
    parser.add_argument("--method", default="auto")
    parser.add_argument("--max-patch-area", type=float, default=0.05)
    parser.add_argument("--check")
    args = parser.parse_args()
    if args.check:
        return check(args)
    if not args.out:
        parser.error("OUT.json or --check RESULT.json is required")
    write(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
