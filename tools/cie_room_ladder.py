#!/usr/bin/env python3
"""Speed against error for the issue-4 room with interreflection (docs/BENCHMARKS.md).

A 6 x 4 x 3 m room, every surface rho = 0.5, a 1 m2 Lambertian panel (L = 1 W m-2 sr-1 nm-1) set
flush into the ceiling (the ceiling mesh has the matching hole), 384 sensors 1 cm above the floor.
There is no closed form with interreflection: each rung is compared with the finest rung's sensors.

usage: tools/cie_room_ladder.py LAMBERT OUTDIR [PATCHES ...]
Writes OUTDIR/cie_room_<patches>.json (scenes) and OUTDIR/result_<patches>.json, and prints a table
of patches, time (median of --runs solves) and rms/max sensor error against the last rung.
"""
import json, math, os, statistics, subprocess, sys

def room(target_patches):
    area = 2 * (6 * 4 + 6 * 3 + 4 * 3)
    ring_v = [[0, 0, 3], [6, 0, 3], [6, 4, 3], [0, 4, 3], [2.5, 1.5, 3], [3.5, 1.5, 3], [3.5, 2.5, 3], [2.5, 2.5, 3]]
    # Ceiling faces down (-z): triangles clockwise seen from above.
    ring_t = [[0, 4, 1], [1, 4, 5], [1, 5, 2], [2, 5, 6], [2, 6, 3], [3, 6, 7], [3, 7, 0], [0, 7, 4]]
    V = [[0, 0, 0], [6, 0, 0], [6, 4, 0], [0, 4, 0], [0, 0, 3], [6, 0, 3], [6, 4, 3], [0, 4, 3]]
    T = [[0, 1, 2], [0, 2, 3],          # floor, +z
         [0, 4, 5], [0, 5, 1],          # y = 0, +y
         [3, 2, 6], [3, 6, 7],          # y = 4, -y
         [0, 3, 7], [0, 7, 4],          # x = 0, +x
         [1, 5, 6], [1, 6, 2]]          # x = 6, -x
    return {
        "lambert": 1, "name": "cie-room-rho0.5",
        "description": "issue 4: 6 x 4 x 3 m room, rho = 0.5, 1 m2 Lambertian panel flush in the ceiling, 384 sensors",
        "spectrum": {"mode": "spectral", "wavelengths_nm": [555]},
        "materials": {"grey": {"reflectance": 0.5}},
        "surfaces": [
            {"name": "walls-floor", "material": "grey", "mesh": {"vertices": V, "triangles": T}},
            {"name": "ceiling", "material": "grey", "mesh": {"vertices": ring_v, "triangles": ring_t}},
            {"name": "panel", "material": "grey", "polygon": [[2.5, 1.5, 3], [2.5, 2.5, 3], [3.5, 2.5, 3], [3.5, 1.5, 3]],
             "emission": {"radiance": 1.0}},
        ],
        "probes": [{"name": "sensors", "normal": [0, 0, 1],
                    "grid": {"origin": [0, 0, 0.01], "u": [6, 0, 0], "v": [0, 4, 0], "nu": 24, "nv": 16}}],
        "meshing": {"max_patch_area": area / target_patches},
        "solver": {"method": "dense"},
    }

def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    runs = 1
    for a in sys.argv[1:]:
        if a.startswith("--runs="): runs = int(a.split("=")[1])
    lambert, out = args[0], args[1]
    rungs = [int(x) for x in args[2:]] or [500, 1000, 2000, 3000, 16000]
    os.makedirs(out, exist_ok=True)
    rows = []
    for n in rungs:
        scene = os.path.join(out, f"cie_room_{n}.json")
        result = os.path.join(out, f"result_{n}.json")
        json.dump(room(n), open(scene, "w"))
        times = []
        for _ in range(runs if n != rungs[-1] else 1):
            subprocess.run([lambert, "solve", scene, "-o", result], check=True, stdout=subprocess.DEVNULL)
            times.append(json.load(open(result))["stats"]["time_s"]["total"])
        d = json.load(open(result))
        rows.append((n, d["stats"]["patches"], statistics.median(times), d["probes"][0]["illuminance_lx"]))
    ref = rows[-1][3]
    print("| patches | time (s) | rms | max |")
    print("|---:|---:|---:|---:|")
    for n, patches, t, e in rows[:-1]:
        err = [x / y - 1 for x, y in zip(e, ref)]
        rms = math.sqrt(sum(x * x for x in err) / len(err))
        print(f"| {patches} | {t:.2f} | {100 * rms:.3f} % | {100 * max(map(abs, err)):.3f} % |")
    print(f"(reference: {rows[-1][1]} patches, {rows[-1][2]:.1f} s)")

if __name__ == "__main__":
    main()
