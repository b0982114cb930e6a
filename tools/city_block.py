#!/usr/bin/env python3
"""Writes the city-block benchmark scene of docs/BENCHMARKS.md ("A 22 000-triangle scene").

N x M buildings (boxes without bottoms, 8 m square on a 12 m pitch, heights drawn uniformly from
6-30 m with a fixed seed) stand on a ground plane and are lit by the sun (a directional light,
1 W/m^2/nm at one wavelength). Facades and roofs reflect 0.4, the ground 0.2. Every box has
10 triangles; the ground adds 2, so 46 x 48 gives 22 082 input triangles.

usage: tools/city_block.py N M OUT.json [--accuracy A] [--method auto|dense|hierarchical]
"""
import argparse
import json
import random


def quad(vertices, triangles, a, b, c, d):
    i = len(vertices)
    vertices.extend([a, b, c, d])
    triangles.extend([[i, i + 1, i + 2], [i, i + 2, i + 3]])


def city(n, m):
    rng = random.Random(1)
    vertices, triangles = [], []
    pitch, size = 12.0, 8.0
    for i in range(n):
        for j in range(m):
            x0, y0 = i * pitch, j * pitch
            x1, y1 = x0 + size, y0 + size
            h = rng.uniform(6, 30)
            quad(vertices, triangles, [x0, y0, h], [x1, y0, h], [x1, y1, h], [x0, y1, h])  # roof, +z
            quad(vertices, triangles, [x0, y0, 0], [x1, y0, 0], [x1, y0, h], [x0, y0, h])  # -y
            quad(vertices, triangles, [x1, y1, 0], [x0, y1, 0], [x0, y1, h], [x1, y1, h])  # +y
            quad(vertices, triangles, [x0, y1, 0], [x0, y0, 0], [x0, y0, h], [x0, y1, h])  # -x
            quad(vertices, triangles, [x1, y0, 0], [x1, y1, 0], [x1, y1, h], [x1, y0, h])  # +x
    width, depth = n * pitch, m * pitch
    ground = {"vertices": [[-10, -10, 0], [width + 10, -10, 0], [width + 10, depth + 10, 0], [-10, depth + 10, 0]],
              "triangles": [[0, 1, 2], [0, 2, 3]]}
    return {
        "lambert": 1,
        "name": "city-block",
        "spectrum": {"mode": "spectral", "wavelengths_nm": [555]},
        "materials": {"facade": {"reflectance": 0.4}, "ground": {"reflectance": 0.2}},
        "surfaces": [{"name": "ground", "material": "ground", "mesh": ground},
                     {"name": "buildings", "material": "facade", "mesh": {"vertices": vertices, "triangles": triangles}}],
        "lights": [{"type": "directional", "direction": [0.3, 0.5, -0.8], "irradiance": 1.0}],
    }, len(triangles) + 2


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("n", type=int)
    parser.add_argument("m", type=int)
    parser.add_argument("out")
    parser.add_argument("--accuracy", type=float)
    parser.add_argument("--method", choices=["auto", "dense", "hierarchical"])
    args = parser.parse_args()
    scene, count = city(args.n, args.m)
    solver = {}
    if args.accuracy is not None:
        solver["accuracy"] = args.accuracy
    if args.method:
        solver["method"] = args.method
    if solver:
        scene["solver"] = solver
    with open(args.out, "w") as f:
        json.dump(scene, f)
    print(f"{args.out}: {count} triangles")


if __name__ == "__main__":
    main()
