#!/usr/bin/env python3
"""The scaling office (lambert bench --scaling) as a CAD export would give it: every face a grid of small
squares, two triangles each, the floor without the cells under the desks. A furnace (rho = 0.5, M = 1
everywhere: B = 2 on every patch). docs/BENCHMARKS.md, "10^6 input triangles".

usage: tools/fine_office.py OUT.json STEP_FLOOR_AND_DESKS STEP_WALLS_AND_CEILING
(metres; 0.05 0.03 gives 1 148 222 triangles, 0.1 0.1 gives 154 400)
"""
import json, sys

out, sf, sw = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
V = []; T = []
def grid(o, u, v, nu, nv, skip=None):
    base = len(V)
    for j in range(nv + 1):
        for i in range(nu + 1):
            V.append([round(o[k] + u[k] * i / nu + v[k] * j / nv, 9) for k in range(3)])
    for j in range(nv):
        for i in range(nu):
            if skip and skip(i, j): continue
            a = base + j * (nu + 1) + i; b = a + 1; c = a + nu + 1; d = c + 1
            T.append([a, b, d]); T.append([a, d, c])
desks = [(1 + 1.9 * i, 0.8 + 1.8 * j) for i in range(10) for j in range(5)]
nfx, nfy = round(20 / sf), round(10 / sf)
def under_desk(i, j):
    x, y = (i + 0.5) * sf, (j + 0.5) * sf
    return any(dx < x < dx + 1.6 and dy < y < dy + 0.8 for dx, dy in desks)
# room, normals inward: floor up (+z), ceiling down, walls inward
grid([0, 0, 0], [20, 0, 0], [0, 10, 0], nfx, nfy, under_desk)            # floor: u x v = +z
n = lambda L: max(1, round(L / sw))
grid([0, 0, 3], [0, 10, 0], [20, 0, 0], n(10), n(20))                   # ceiling: -z
grid([0, 0, 0], [0, 0, 3], [20, 0, 0], n(3), n(20))                     # y = 0 wall: (0,0,3)x(20,0,0) = +y
grid([0, 10, 0], [20, 0, 0], [0, 0, 3], n(20), n(3))                    # y = 10: (20,0,0)x(0,0,3) = -y
grid([0, 0, 0], [0, 10, 0], [0, 0, 3], n(10), n(3))                     # x = 0: (0,10,0)x(0,0,3) = +x
grid([20, 0, 0], [0, 0, 3], [0, 10, 0], n(3), n(10))                    # x = 20: -x
room_tris = len(T)
m = lambda L: max(1, round(L / sf))
for dx, dy in desks:
    h = 0.75
    grid([dx, dy, h], [1.6, 0, 0], [0, 0.8, 0], m(1.6), m(0.8))        # top +z
    grid([dx, dy, 0], [1.6, 0, 0], [0, 0, h], m(1.6), m(h))            # y = dy side: (1.6,0,0)x(0,0,h) = -y (outward)
    grid([dx, dy + 0.8, 0], [0, 0, h], [1.6, 0, 0], m(h), m(1.6))      # +y
    grid([dx, dy, 0], [0, 0, h], [0, 0.8, 0], m(h), m(0.8))            # x = dx: (0,0,h)x(0,0.8,0) = -x
    grid([dx + 1.6, dy, 0], [0, 0.8, 0], [0, 0, h], m(0.8), m(h))      # +x
scene = {"lambert": 1, "name": "office-furnace-fine",
         "spectrum": {"mode": "spectral", "wavelengths_nm": [555]},
         "materials": {"grey": {"reflectance": 0.5}},
         "surfaces": [{"name": "office", "material": "grey", "mesh": {"vertices": V, "triangles": T},
                       "emission": {"exitance": 1.0}}],
         "solver": {"method": "hierarchical"}}
json.dump(scene, open(out, "w"), separators=(",", ":"))
print(len(T), "triangles", len(V), "vertices")
