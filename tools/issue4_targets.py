#!/usr/bin/env python3
"""Measures issue 4's targets in one sitting, so that they can be re-measured on another machine.

Each row is one target of issue 4 ("Targets"), measured with the scene generators of this folder and
`lambert solve` / `lambert bench`, and compared with an independent answer where the target names an
error: a finer solve of the same scene (self-convergence) or the furnace's closed form. Times are
`stats.time_s.total` (the solver's own clock, without JSON input and output), medians of --runs
solves; peak memory is the child process's maximum resident set.

usage: tools/issue4_targets.py LAMBERT [--out DIR] [--runs N] [--million]
  --million   also the lit 10^6-triangle sphere room (sphere_room.py 5 8 6 --lit): about 9 minutes
              and 7.5 GiB on the machine of docs/BENCHMARKS.md
Prints a Markdown table; DIR keeps the scenes and results (default /tmp/lambert-targets).
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys

TOOLS = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, TOOLS)

from cie_room_ladder import room as cie_room_scene  # noqa: E402
import cube_room_furnace  # noqa: E402
from cube_room_furnace import box  # noqa: E402


def run(lambert, scene, result, extra=()):
    """Solves `scene` into `result`; returns (stats, peak resident MiB)."""
    with open(os.devnull, "w") as quiet:
        child = subprocess.Popen([lambert, "solve", scene, "-o", result, *extra], stdout=quiet, stderr=quiet)
        _, status, usage = os.wait4(child.pid, 0)
    if status != 0:
        sys.exit(f"lambert solve {scene} failed (status {status})")
    with open(result) as f:
        stats = json.load(f)["stats"]
    return stats, usage.ru_maxrss / 1024


def timed(lambert, scene, result, runs):
    """Median total time of `runs` solves, the last result's stats and the largest peak memory."""
    times, peak, stats = [], 0.0, None
    for _ in range(runs):
        stats, mib = run(lambert, scene, result)
        times.append(stats["time_s"]["total"])
        peak = max(peak, mib)
    return statistics.median(times), stats, peak


def write(path, scene):
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def load(path):
    with open(path) as f:
        return json.load(f)


def relative_errors(values, reference):
    return [abs(v - r) / abs(r) for v, r in zip(values, reference) if r != 0]


def rms(errors):
    return math.sqrt(sum(e * e for e in errors) / len(errors))


def cie_room(lambert, out, runs):
    """6 x 4 x 3 m room, rho = 0.5, 1 m^2 ceiling panel, 384 sensors: rms sensor error against a
    solve at about 18 600 patches."""
    scene = write(f"{out}/cie_room.json", cie_room_scene(1500))
    reference = write(f"{out}/cie_room_reference.json", cie_room_scene(12000))
    run(lambert, reference, f"{out}/cie_room_reference.result.json")
    t, stats, peak = timed(lambert, scene, f"{out}/cie_room.result.json", runs)
    e = relative_errors(load(f"{out}/cie_room.result.json")["probes"][0]["illuminance_lx"],
                        load(f"{out}/cie_room_reference.result.json")["probes"][0]["illuminance_lx"])
    return ("CIE-style room, ρ = 0.5, 384 sensors", "≤ 0.1 % rms in ≤ 1.8 s", stats["patches"], t, peak,
            f"{100 * rms(e):.3f} % rms (max {100 * max(e):.2f} %)", rms(e) <= 1e-3 and t <= 1.8)


def cube_room(lambert, out, runs):
    """The same room with a floating 1 m cube, a furnace (rho = 0.5, M = 1: B = 2), about 16 000
    patches, hierarchical with exact visibility: the closure (largest row-sum correction) and B."""
    scene = cube_room_furnace.scene(0.01)
    scene["solver"]["exact_visibility"] = True
    path = write(f"{out}/cube_room.json", scene)
    t, stats, peak = timed(lambert, path, f"{out}/cube_room.result.json", runs)
    worst_b = max(abs(p["radiosity"][0] / 2 - 1) for p in load(f"{out}/cube_room.result.json")["patches"])
    closure = stats["closure_max_error"]
    return ("cube room furnace, exact visibility", "closure ≤ 1e-4 in ≤ 10 s", stats["patches"], t, peak,
            f"closure {closure:.2g}, B within {worst_b:.1g} of 2 (relative)", closure <= 1e-4 and t <= 10)


def cornell(lambert, out, runs):
    """The bundled Cornell box (measured data, 61 wavelengths): worst surface luminance error against
    the same scene at 400 mm^2."""
    bundled = load(os.path.join(TOOLS, "..", "scenes", "cornell-box.json"))
    scene = write(f"{out}/cornell.json", bundled)
    bundled["meshing"]["max_patch_area"] = 400
    reference = write(f"{out}/cornell_reference.json", bundled)
    run(lambert, reference, f"{out}/cornell_reference.result.json")
    t, stats, peak = timed(lambert, scene, f"{out}/cornell.result.json", runs)
    ref = {s["name"]: s["luminance_cd_m2"] for s in load(f"{out}/cornell_reference.result.json")["surfaces"]}
    errors = {s["name"]: abs(s["luminance_cd_m2"] / ref[s["name"]] - 1)
              for s in load(f"{out}/cornell.result.json")["surfaces"] if ref.get(s["name"])}
    errors.pop("light", None)
    worst = max(errors, key=errors.get)
    return ("Cornell box (measured data)", "1 % in < 1 s", stats["patches"], t, peak,
            f"worst surface {100 * errors[worst]:.2f} % ({worst})", errors[worst] <= 0.01 and t < 1)


def city(lambert, out):
    """22 082 input triangles lit by the sun (tools/city_block.py 46 48), default settings."""
    path = f"{out}/city.json"
    subprocess.run([sys.executable, os.path.join(TOOLS, "city_block.py"), "46", "48", path], check=True,
                   stdout=subprocess.DEVNULL)
    stats, peak = run(lambert, path, f"{out}/city.result.json")
    t = stats["time_s"]["total"]
    return ("city block, 22 082 triangles", "< 60 s", stats["patches"], t, peak,
            f"{stats['links']:,} links, {stats['rays']:,} rays", t < 60)


def grey(lambert, out, runs):
    """A grey room (rho = 0.6, floating cube, ceiling panel) with 1 and with 81 wavelengths."""
    def scene(wavelengths):
        return {
            "lambert": 1, "name": f"grey-{len(wavelengths)}",
            "spectrum": {"mode": "spectral", "wavelengths_nm": wavelengths},
            "materials": {"grey": {"reflectance": 0.6}},
            "surfaces": [
                {"name": "room", "material": "grey", "mesh": box((0, 0, 0), (6, 4, 3), True)},
                {"name": "cube", "material": "grey", "mesh": box((2.5, 1.5, 1), (3.5, 2.5, 2), False)},
                {"name": "panel", "material": "grey", "emission": {"radiance": 1.0},
                 "polygon": [[2.5, 1.5, 2.999], [2.5, 2.5, 2.999], [3.5, 2.5, 2.999], [3.5, 1.5, 2.999]]},
            ],
            "meshing": {"max_patch_area": 0.045},
        }
    one, one_stats, _ = timed(lambert, write(f"{out}/grey1.json", scene([555])), f"{out}/grey1.result.json", runs)
    many, stats, peak = timed(lambert, write(f"{out}/grey81.json", scene(list(range(380, 781, 5)))),
                              f"{out}/grey81.result.json", runs)
    return ("grey scene, 81 wavelengths", "≤ 1.1 × one wavelength", stats["patches"], many, peak,
            f"{many / one:.2f} × ({one:.2f} s for one; systems solved {stats['spectral_systems_solved']})",
            many <= 1.1 * one)


def ray_cost(lambert, out):
    """`lambert bench`'s ray-cost table: solver ns per link ray against Embree's raw row-ordered rays."""
    path = f"{out}/bench.json"
    subprocess.run([lambert, "bench", "-o", path], check=True, stdout=subprocess.DEVNULL)
    rows = []
    for r in load(path)["ray_cost"]:
        rows.append((f"ray cost, {r['scene']}", "≤ 2 × Embree's raw rays", r["patches"], None, None,
                     f"{r['solver_ns_per_ray_per_thread']:.1f} ns/ray, {r['ratio_to_coherent']:.2f} × raw rows",
                     r["ratio_to_coherent"] <= 2))
    return rows


def million(lambert, out):
    """The lit 10^6-triangle room: 48 faceted spheres of 20 480 triangles under a ceiling panel."""
    path = f"{out}/million.json"
    subprocess.run([sys.executable, os.path.join(TOOLS, "sphere_room.py"), path, "5", "8", "6", "--lit"], check=True,
                   stdout=subprocess.DEVNULL)
    stats, peak = run(lambert, path, f"{out}/million.result.json")
    t = stats["time_s"]["total"]
    return ("lit sphere room, 983 052 triangles", "< 10 min and 8 GiB", stats["patches"], t, peak,
            f"{stats['links']:,} links, {stats['rays']:,} rays", t < 600 and peak < 8 * 1024)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("lambert")
    parser.add_argument("--out", default="/tmp/lambert-targets")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--million", action="store_true")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    lambert = os.path.abspath(args.lambert)
    rows = [cie_room(lambert, args.out, args.runs), cube_room(lambert, args.out, args.runs),
            cornell(lambert, args.out, args.runs), city(lambert, args.out), grey(lambert, args.out, args.runs)]
    rows += ray_cost(lambert, args.out)
    if args.million:
        rows.append(million(lambert, args.out))
    print("| target | asked | patches | time (s) | peak MiB | measured | met |")
    print("|---|---|---:|---:|---:|---|---|")
    for name, asked, patches, t, peak, measured, met in rows:
        time_text = "" if t is None else f"{t:.2f}"
        peak_text = "" if peak is None else f"{peak:,.0f}"
        print(f"| {name} | {asked} | {patches:,} | {time_text} | {peak_text} | {measured} | {'yes' if met else 'no'} |")


if __name__ == "__main__":
    main()
