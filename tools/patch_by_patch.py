#!/usr/bin/env python3
"""Compares two results of one scene patch by patch, on the patches both share.

Two solves of a scene (for example `solver.method` hierarchical and dense) mesh it alike where the
input triangles are the patches (faceted objects) and often elsewhere too; a patch is matched by its
three corners. For each surface group (a surface's name up to its first space, so "sphere 0 1" and
"sphere 2 0" count as "sphere") it prints the relative error of TEST's patch illuminance against
REFERENCE's: rms, median, 95th percentile and worst, and the worst patch's centroid. Surface means
hide what this shows (docs/BENCHMARKS.md, "Patch by patch").

usage: tools/patch_by_patch.py TEST.json REFERENCE.json [--key illuminance_lx]
"""
import argparse
import json
import math


def corners(patch):
    return tuple(sorted(tuple(round(c, 9) for c in v) for v in patch["vertices"]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("test")
    parser.add_argument("reference")
    parser.add_argument("--key", default="illuminance_lx", help="a per-patch number of the result")
    args = parser.parse_args()
    with open(args.test) as f:
        test = json.load(f)
    with open(args.reference) as f:
        reference = json.load(f)
    by_corners = {corners(p): p for p in reference["patches"]}
    groups = {}
    unmatched = 0
    for p in test["patches"]:
        q = by_corners.get(corners(p))
        if q is None or not q[args.key] > 0:
            unmatched += 1
            continue
        error = p[args.key] / q[args.key] - 1
        centroid = [round(sum(v[k] for v in p["vertices"]) / 3, 3) for k in range(3)]
        groups.setdefault(p["surface"].split(" ")[0], []).append((error, centroid))
    print(f"{len(test['patches']) - unmatched} patches shared, {unmatched} not")
    print("| surface | patches | rms | median | p95 | worst | worst at |")
    print("|---|---:|---:|---:|---:|---:|---|")
    for name, rows in sorted(groups.items()):
        size = sorted(abs(e) for e, _ in rows)
        worst = max(rows, key=lambda r: abs(r[0]))
        rms = math.sqrt(sum(e * e for e, _ in rows) / len(rows))
        print(f"| {name} | {len(rows)} | {100 * rms:.3f} % | {100 * size[len(size) // 2]:.3f} % | "
              f"{100 * size[int(0.95 * (len(size) - 1))]:.2f} % | {100 * worst[0]:+.2f} % | {worst[1]} |")


if __name__ == "__main__":
    main()
