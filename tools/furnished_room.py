#!/usr/bin/env python3
"""Writes the furnished room of docs/BENCHMARKS.md ("A furnished room by `auto` at 2 800–70 000 patches").

A 6 x 4 x 3 m room (walls and ceiling rho = 0.5, floor 0.3) with a cabinet standing in a corner
(contacts with the floor and two walls), a stool on the floor (a contact), and a table top floating at
0.70-0.75 m (an occluder), all rho = 0.5. Lit by a 1 m^2 Lambertian panel 1 mm under the ceiling
(M = 10 W m-2 nm-1, one wavelength) and an isotropic point source (20 W sr-1 nm-1). Sensors: a work
plane at 0.85 m (24 x 16, facing up) and the floor beside and under the table (12 x 8, 1 cm up).
There is no closed form: each solve is compared with a dense solve on finer patches.

usage: tools/furnished_room.py OUT.json TARGET_PATCHES [--method auto|dense|hierarchical] [--accuracy A]
"""
import argparse
import json

from cube_room_furnace import box

AREA = 2 * (6 * 4 + 6 * 3 + 4 * 3)  # the room's surface, m^2 (the furniture adds about 9 %)


def floor_and_walls(size):
    """A room's inward box from the origin to `size`, as its floor and the rest (walls and ceiling)."""
    room = box((0, 0, 0), size, True)
    floor = {"vertices": room["vertices"][:4], "triangles": room["triangles"][:2]}
    walls = {"vertices": room["vertices"][4:], "triangles": [[a - 4, b - 4, c - 4] for a, b, c in room["triangles"][2:]]}
    return floor, walls


def solver_settings(method, accuracy):
    solver = {"method": method}
    if accuracy is not None:
        solver["accuracy"] = accuracy
    return solver


def scene(target_patches, method, accuracy):
    floor, walls = floor_and_walls((6, 4, 3))
    solver = solver_settings(method, accuracy)
    return {
        "lambert": 1, "name": "furnished-room",
        "description": "6 x 4 x 3 m room, a cabinet and a stool on the floor, a floating table top, a ceiling panel and a point source",
        "spectrum": {"mode": "spectral", "wavelengths_nm": [555]},
        "materials": {"grey": {"reflectance": 0.5}, "floor": {"reflectance": 0.3}},
        "surfaces": [
            {"name": "floor", "material": "floor", "mesh": floor},
            {"name": "walls-ceiling", "material": "grey", "mesh": walls},
            {"name": "cabinet", "material": "grey", "mesh": box((0, 2.8, 0), (0.5, 4, 2), False)},
            {"name": "stool", "material": "grey", "mesh": box((3.6, 2.2, 0), (4.1, 2.7, 0.45), False)},
            {"name": "table", "material": "grey", "mesh": box((1.5, 1.2, 0.7), (3.1, 2.0, 0.75), False)},
            {"name": "panel", "material": "grey", "emission": {"exitance": 10.0},
             "polygon": [[2.5, 1.5, 2.999], [2.5, 2.5, 2.999], [3.5, 2.5, 2.999], [3.5, 1.5, 2.999]]},
        ],
        "lights": [{"type": "point", "position": [4.5, 1.0, 2.5], "intensity": 20.0}],
        "probes": [
            {"name": "work plane", "normal": [0, 0, 1],
             "grid": {"origin": [0.6, 0, 0.85], "u": [5.4, 0, 0], "v": [0, 4, 0], "nu": 24, "nv": 16}},
            {"name": "floor", "normal": [0, 0, 1],
             "grid": {"origin": [0.6, 0, 0.01], "u": [2.9, 0, 0], "v": [0, 2.1, 0], "nu": 12, "nv": 8}},
        ],
        "meshing": {"max_patch_area": AREA / target_patches},
        "solver": solver,
    }


def run_cli(doc, make_scene):
    """The command line of the room generators: OUT.json TARGET_PATCHES [--method] [--accuracy]."""
    parser = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    parser.add_argument("target_patches", type=float)
    parser.add_argument("--method", default="auto")
    parser.add_argument("--accuracy", type=float)
    args = parser.parse_args()
    with open(args.out, "w") as f:
        json.dump(make_scene(args.target_patches, args.method, args.accuracy), f)


if __name__ == "__main__":
    run_cli(__doc__, scene)
