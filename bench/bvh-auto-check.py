#!/usr/bin/env python3
"""How close `bvh:build=auto` comes to the best builder's total time (build + trace) on
each scene of a `prism bench` run with every builder, at 1 and 64 passes (a pass: the
bench's camera and shadow rays once, as a render traces them per path per pixel).

check: auto as measured, the rows `bvh:build=auto@1` and `@64` of a run with
`--auto-passes 1,64` (each built for that many passes' rays, traced in turns with the
others), against the best of the other rows; what auto chose is the candidate whose
tree its row matches, node for node.
fit: the model's constants for crates/prism/src/accel/bvh/build/auto.rs from runs of
the same kind: per candidate and kind of scene (all triangles or not) the geometric mean
over the scenes of all the runs of its build time per primitive and of its pass time
relative to binned SAH's, and binned's mean pass time per ray; then, per run, which
candidate the model with those constants would pick per cell and how close its own row
comes to the best, on the runs it was fitted on and on those after --test (out of sample).
Usage:
  bench/bvh-auto-check.py check RUN.csv
  bench/bvh-auto-check.py fit RUN.csv... [--test RUN.csv...] [CANDIDATE...]
      (candidates as lbvh, binned, binned,reinsert, ploc, sbvh,reinsert...; default the
      model's: lbvh binned binned,reinsert)"""
import csv
import math
import sys

PASSES = (1, 64)
TRIANGLE_SCENES = {"stadium", "slivers", "shards", "teapot", "gears", "stanford-bunny"}


def pass_ms(r):
    """One pass: the camera and the shadow rays, ms."""
    return (int(r["primary_rays"]) / float(r["primary_mrays_per_s"])
            + int(r["shadow_rays"]) / float(r["shadow_mrays_per_s"])) / 1e3


def short(m):
    if m == "bvh":
        return "binned"
    return m.replace("bvh:build=", "").replace("bvh:", "binned,")


def load(path):
    scenes = {}
    for row in csv.DictReader(open(path)):
        if row["status"] == "ok":
            scenes.setdefault(row["scene"], {})[row["method"]] = row
    return scenes


def total(r, passes):
    return float(r["build_ms"]) + passes * pass_ms(r)


def builders(runs):
    return {m: r for m, r in runs.items() if "auto" not in m}


def tree(r):
    return tuple(r[c] for c in ("nodes", "leaves", "depth", "sah_cost", "memory_bytes"))


def chosen(runs, auto):
    """The candidate whose tree is auto's, node for node (binned before its look-alikes)."""
    for name in ("lbvh", "binned", "binned,reinsert"):
        if tree(runs[spec(name)]) == tree(runs[auto]):
            return name
    return "?"


def check(csv_path):
    scenes = load(csv_path)
    print("| scene | passes | auto chose | best | auto / best | binned / best |")
    print("|---|---:|---|---|---:|---:|")
    within = 0
    cells = 0
    for passes in PASSES:
        for scene, runs in scenes.items():
            auto = f"bvh:build=auto@{passes}"
            times = {m: total(r, passes) for m, r in builders(runs).items()}
            best = min(times, key=times.get)
            ratio = total(runs[auto], passes) / times[best]
            cells += 1
            within += ratio <= 1.10
            print(f"| {scene} | {passes} | {chosen(runs, auto)} | {short(best)} | "
                  f"{ratio:.2f} | {times['bvh'] / times[best]:.2f} |")
    print(f"\nauto within 10 % of the best: {within} of {cells}")


def geomean(values):
    return math.exp(sum(math.log(v) for v in values) / len(values))


SPECS = {"lbvh": "bvh:build=lbvh", "binned": "bvh", "binned,reinsert": "bvh:reinsert"}


def spec(name):
    if name in SPECS:
        return SPECS[name]
    base, _, reinsert = name.partition(",")
    return f"bvh:build={base}" + (",reinsert" if reinsert else "")


def fit(csv_paths, test_paths, names):
    runs = [load(p) for p in csv_paths]
    model = {}
    for triangles in (True, False):
        kind = [r for scenes in runs for s, r in scenes.items() if (s in TRIANGLE_SCENES) == triangles]
        ns_per_ray = geomean([pass_ms(r["bvh"]) * 1e6 / (int(r["bvh"]["primary_rays"]) + int(r["bvh"]["shadow_rays"]))
                              for r in kind])
        rows = []
        for name in names:
            m = spec(name)
            build = geomean([float(r[m]["build_ms"]) * 1e6 / int(r[m]["primitives"]) for r in kind])
            trace = geomean([pass_ms(r[m]) / pass_ms(r["bvh"]) for r in kind])
            rows.append((name, build, trace))
        model[triangles] = (rows, ns_per_ray)
        print(f"{'triangles' if triangles else 'other shapes'}: binned {ns_per_ray:.0f} ns per ray; "
              + ", ".join(f"{n} {b:.0f} ns/prim x{t:.3f}" for n, b, t in rows))
    for path, scenes in [(p, load(p)) for p in csv_paths + test_paths]:
        within = 0
        cells = 0
        for passes in PASSES:
            for scene, runs_of_scene in scenes.items():
                rows, ns_per_ray = model[scene in TRIANGLE_SCENES]
                r = runs_of_scene["bvh"]
                n = int(r["primitives"])
                rays = passes * (int(r["primary_rays"]) + int(r["shadow_rays"]))
                pick = min(rows, key=lambda c: n * c[1] + rays * ns_per_ray * c[2])[0]
                times = {m: total(x, passes) for m, x in builders(runs_of_scene).items()}
                best = min(times, key=times.get)
                ratio = times[spec(pick)] / times[best]
                cells += 1
                within += ratio <= 1.10
                print(f"{scene:16} {passes:3} model picks {pick:16} best {short(best):18} {ratio:.2f}")
        sample = "in sample" if path in csv_paths else "out of sample"
        print(f"{path} ({sample}): the model within 10 % of the best: {within} of {cells}")


if __name__ == "__main__":
    if len(sys.argv) >= 3 and sys.argv[1] == "check":
        check(sys.argv[2])
    elif len(sys.argv) >= 3 and sys.argv[1] == "fit":
        args = sys.argv[2:]
        test = args.index("--test") if "--test" in args else len(args)
        paths = [a for a in args[:test] if a.endswith(".csv")]
        tests = [a for a in args[test:] if a.endswith(".csv")]
        names = [a for a in args if not a.endswith(".csv") and a != "--test"]
        fit(paths, tests, names or ["lbvh", "binned", "binned,reinsert"])
    else:
        sys.exit(__doc__)
