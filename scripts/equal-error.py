#!/usr/bin/env python3
"""Rays at equal error between the adaptive families of a `prism sweep` table.

For each family (rule:jitter:texture_spp) the points on its front (no other point of the
family has both fewer rays and lower error) are listed; for each, the rays another family
needs for the same error, interpolated log-log along that family's front, or '-' where its
front does not reach that error. Usage: equal-error.py SWEEP.csv [...]
"""
import csv
import math
import sys


def front(rows, metric):
    points = sorted((float(r["rays_per_pixel"]), float(r[metric]), r["label"]) for r in rows)
    out, best = [], math.inf
    for rays, err, label in points:
        if err < best:
            out.append((rays, err, label))
            best = err
    return out


def rays_at(points, err):
    for (x0, e0, _), (x1, e1, _) in zip(points, points[1:]):
        if e1 <= err <= e0:
            t = 0.0 if e0 == e1 else (math.log(err) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(x0) + t * (math.log(x1) - math.log(x0)))
    return None


for path in sys.argv[1:]:
    rows = list(csv.DictReader(open(path)))
    families = {}
    for r in rows:
        families.setdefault(f"{r['rule']}:{r['jitter']}:{r['texture_spp']}", []).append(r)
    print(f"== {path}")
    for metric in ("rmse", "flip"):
        fronts = {k: front(v, metric) for k, v in families.items()}
        for name, points in sorted(fronts.items()):
            for rays, err, label in points:
                others = []
                for other, their in sorted(fronts.items()):
                    if other == name:
                        continue
                    need = rays_at(their, err)
                    others.append(f"{other} {'-' if need is None else f'{need:.1f} ({need / rays:.2f}x)'}")
                print(f"  {metric:4} {label:44} {rays:8.2f} rays/px {err:.5f}  | " + "; ".join(others))
