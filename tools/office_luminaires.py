#!/usr/bin/env python3
"""The bundled open office lit by real luminaires (scenes/office-luminaires.json): 20 x 10 x 3 m, ten
desks, 60 luminaires from photometric files (scenes/luminaires/, README there) 1 cm under the ceiling,
a 50 x 40 = 2000-point work-plane grid at 0.8 m. docs/BENCHMARKS.md times it at the default settings.

usage: tools/office_luminaires.py [OUT.json]   (default: scenes/office-luminaires.json)
"""
import json, os, sys

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "scenes", "office-luminaires.json")

def quad(name, material, a, b, c, d):
    return {"name": name, "material": material, "polygon": [a, b, c, d]}

surfaces = [
    quad("floor", "floor", [0, 0, 0], [20, 0, 0], [20, 10, 0], [0, 10, 0]),          # faces +z
    quad("ceiling", "ceiling", [0, 0, 3], [0, 10, 3], [20, 10, 3], [20, 0, 3]),      # faces -z
    quad("wall south", "wall", [0, 0, 0], [0, 0, 3], [20, 0, 3], [20, 0, 0]),        # faces +y
    quad("wall north", "wall", [0, 10, 0], [20, 10, 0], [20, 10, 3], [0, 10, 3]),    # faces -y
    quad("wall west", "wall", [0, 0, 0], [0, 10, 0], [0, 10, 3], [0, 0, 3]),         # faces +x
    quad("wall east", "wall", [20, 0, 0], [20, 0, 3], [20, 10, 3], [20, 10, 0]),     # faces -x
]
# Ten desks, 1.6 x 0.8 x 0.75 m boxes standing on the floor (outward normals).
for i, (x, y) in enumerate([(2 + 3.6 * k, 2.6) for k in range(5)] + [(2 + 3.6 * k, 6.6) for k in range(5)]):
    X, Y, H = x + 1.6, y + 0.8, 0.75
    v = [[x, y, 0], [X, y, 0], [X, Y, 0], [x, Y, 0], [x, y, H], [X, y, H], [X, Y, H], [x, Y, H]]
    t = [[4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]]
    surfaces.append({"name": "desk %d" % (i + 1), "material": "desk", "mesh": {"vertices": v, "triangles": t}})

lights = []
def luminaire(name, path, x, y, z=2.99):
    return {"type": "luminaire", "name": name, "photometry": {"file": path}, "position": [x, y, z],
            "nadir": [0, 0, -1], "c0": [1, 0, 0], "maintenance_factor": 0.8, "spectrum": {"blackbody_K": 3000}}
# 10 x 5 BEGA 50899 downlights over the desks and aisles, 2 Cooper Shaper ceiling luminaires by the
# entrance (west wall), 8 BEGA 50975 downlights along the east wall.
for i in range(10):
    for j in range(5):
        lights.append(luminaire("D%d-%d" % (i + 1, j + 1), "luminaires/bega-50899-downlight.ies", 1 + 2 * i, 1 + 2 * j))
for j, y in enumerate([3, 7]):
    # Its luminous cylinder (0.44 m high) is centred on the photometric centre: hung 1 cm below the ceiling.
    lights.append(luminaire("S%d" % (j + 1), "luminaires/cooper-shaper-210d.ies", 0.6, y, 3 - 0.22 - 0.01))
for j in range(8):
    lights.append(luminaire("W%d" % (j + 1), "luminaires/bega-50975-downlight.ldt", 19.7, 0.625 + 1.25 * j))

scene = {
    "lambert": 1,
    "name": "office-luminaires",
    "description": "An open office, 20 x 10 x 3 m with ten desks, lit by 60 luminaires read from the "
                   "manufacturers' photometric files in scenes/luminaires/ (IES LM-63 and EULUMDAT; sources "
                   "in the README there), maintenance factor 0.8; a 2000-point work-plane grid at 0.8 m. "
                   "Written by tools/office_luminaires.py.",
    "units": "m",
    "materials": {"floor": {"reflectance": 0.2}, "wall": {"reflectance": 0.5}, "ceiling": {"reflectance": 0.8},
                  "desk": {"reflectance": 0.4}},
    "surfaces": surfaces,
    "lights": lights,
    "probes": [{"name": "workplane", "grid": {"origin": [0, 0, 0.8], "u": [20, 0, 0], "v": [0, 10, 0],
                                              "nu": 50, "nv": 40}, "normal": [0, 0, 1]}],
    "output": {"spectral": False},
}
with open(out, "w") as f:
    json.dump(scene, f, indent=1)
    f.write("\n")
print("wrote", out, len(lights), "luminaires")
