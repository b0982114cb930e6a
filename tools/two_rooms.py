#!/usr/bin/env python3
"""Writes the two-room scene of docs/BENCHMARKS.md ("A dim room beside a bright one").

Two 5 x 4 x 3 m rooms side by side, joined by a 1 x 2.1 m door in a 0.12 m partition (three boxes
touching the floor, the ceiling and the side walls). Room A (west) holds an isotropic point source
0.4 m under the ceiling; room B (east) a 0.6 m^2 Lambertian panel 1 mm under the ceiling, a desk top
against the south wall and a shelf against the east wall, so that B gathers about a tenth of what A
does. Coloured materials at three wavelengths (walls 0.6-0.75, floor 0.15-0.25, wood 0.2-0.5,
partition 0.85). Sensors: a work plane at 0.8 m in each room (facing up) and the partition's east
face, 1 cm in front of it. There is no closed form: each solve is compared with a dense solve on
finer patches.

usage: tools/two_rooms.py OUT.json TARGET_PATCHES [--method auto|dense|hierarchical] [--accuracy A]
"""
from cube_room_furnace import box
from furnished_room import floor_and_walls, run_cli, solver_settings

NM = [450, 550, 650]
LENGTH = 10.12  # both rooms and the partition, m
AREA = 2 * (LENGTH * 4 + LENGTH * 3 + 4 * 3) + 2 * 4 * 3 * 0.9  # the shell and the partition's faces, m^2


def spectrum(values):
    return {"nm": NM, "values": values}


def scene(target_patches, method, accuracy):
    floor, shell = floor_and_walls((LENGTH, 4, 3))
    return {
        "lambert": 1, "name": "two-rooms",
        "description": "two rooms joined by a door: a point source in the west one, a ceiling panel in the east one",
        "spectrum": {"mode": "spectral", "wavelengths_nm": NM},
        "materials": {
            "wall": {"reflectance": spectrum([0.6, 0.7, 0.75])},
            "floor": {"reflectance": spectrum([0.25, 0.2, 0.15])},
            "wood": {"reflectance": spectrum([0.2, 0.35, 0.5])},
            "white": {"reflectance": 0.85},
        },
        "surfaces": [
            {"name": "floor", "material": "floor", "mesh": floor},
            {"name": "shell", "material": "wall", "mesh": shell},
            {"name": "partition-south", "material": "white", "mesh": box((5, 0, 0), (5.12, 1.5, 3), False)},
            {"name": "partition-north", "material": "white", "mesh": box((5, 2.5, 0), (5.12, 4, 3), False)},
            {"name": "lintel", "material": "white", "mesh": box((5, 1.5, 2.1), (5.12, 2.5, 3), False)},
            {"name": "desk", "material": "wood", "mesh": box((7, 0, 0.72), (8.6, 0.8, 0.76), False)},
            {"name": "shelf", "material": "wood", "mesh": box((9.7, 1, 0), (LENGTH, 3, 1.8), False)},
            {"name": "panel", "material": "white", "emission": {"exitance": spectrum([6.0, 8.0, 7.0])},
             "polygon": [[7.2, 1.5, 2.999], [7.2, 2.5, 2.999], [7.8, 2.5, 2.999], [7.8, 1.5, 2.999]]},
        ],
        "lights": [{"type": "point", "position": [2.0, 2.0, 2.6], "intensity": spectrum([10.0, 12.0, 9.0])}],
        "probes": [
            {"name": "A plane", "normal": [0, 0, 1],
             "grid": {"origin": [0.25, 0.25, 0.8], "u": [4.5, 0, 0], "v": [0, 3.5, 0], "nu": 18, "nv": 14}},
            {"name": "B plane", "normal": [0, 0, 1],
             "grid": {"origin": [5.4, 1.0, 0.8], "u": [4.0, 0, 0], "v": [0, 2.8, 0], "nu": 16, "nv": 11}},
            {"name": "partition B face", "normal": [1, 0, 0],
             "grid": {"origin": [5.13, 0.1, 0.2], "u": [0, 3.8, 0], "v": [0, 0, 2.6], "nu": 19, "nv": 13}},
        ],
        "meshing": {"max_patch_area": AREA / target_patches},
        "solver": solver_settings(method, accuracy),
    }


if __name__ == "__main__":
    run_cli(__doc__, scene)
