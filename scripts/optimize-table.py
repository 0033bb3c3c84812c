#!/usr/bin/env python3
"""The --optimize table of docs/optimisation.md and docs/multi-material.md
(issue 28's targets on the six SPL slices, every label): per slice and
spacing, uniform and graded, the angles and the labels' area errors before
and after the pass, what the pass inserted and removed, and its cost.

    scripts/optimize-table.py build/mesher/warpmesh SLICE_labels16.pgm... [--spacings 1,2]

Each case runs `warpmesh mesh SLICE --materials all --spacing S [--graded]
--threads 1 [--optimize] -o out.vtu --report r.json --quiet` twice (plain and
with --optimize) and prints one Markdown row: angles from the report's
`optimize` section; area errors from its `materials` section (the output
labels, tag 0 not counted): Σ|area − pixel area| / Σ pixel area before (the
mesh before the pass, `area_before_optimize`) and after, the worst label of
>= 500 pixels, the labels whose |area − pixel area| grew; inserted vertices
(of them on interfaces); removed vertices; the `optimize` phase over the rest
of `total_seconds`; the user CPU seconds of the two whole runs (reading and
writing included)."""
import json
import os
import resource
import subprocess
import sys
import tempfile


def run(exe, args, tmp):
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    report = os.path.join(tmp, "r.json")
    subprocess.run([exe, "mesh", *args, "--threads", "1", "-o", os.path.join(tmp, "out.vtu"), "--report", report,
                    "--quiet"], check=True)
    return json.load(open(report)), resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before


def row(exe, path, spacing, graded, tmp):
    name = os.path.basename(path).replace("_labels16.pgm", "").replace("_axial_", " ").replace("_", " ")
    args = [path, "--materials", "all", "--spacing", str(spacing)] + (["--graded"] if graded else [])
    _, user_plain = run(exe, args, tmp)
    r, user_opt = run(exe, args + ["--optimize"], tmp)
    o = r["optimize"]
    labels = [m for m in r["materials"] if m["tag"] != 0 and m["output"] and m["pixel_area"] > 0]
    err_before = [abs(m["area_before_optimize"] - m["pixel_area"]) for m in labels]
    err_after = [abs(m["area"] - m["pixel_area"]) for m in labels]
    pixels = sum(m["pixel_area"] for m in labels)
    big = [(b / m["pixel_area"], a / m["pixel_area"]) for m, b, a in zip(labels, err_before, err_after)
           if m["pixel_area"] >= 500]
    worse = sum(a > b * (1 + 1e-12) + 1e-9 for b, a in zip(err_before, err_after))
    rest = r["total_seconds"] - o["seconds"]
    return (f"| {name}, {spacing:g} px{' graded' if graded else ''} | {o['min_angle_before_deg']:.2f} → "
            f"**{o['min_angle_after_deg']:.2f}** | {o['max_angle_before_deg']:.2f} → {o['max_angle_after_deg']:.2f} | "
            f"{o['mean_min_angle_after_deg']:.2f} | {100 * sum(err_before) / pixels:.3f} % → "
            f"{100 * sum(err_after) / pixels:.3f} % | {100 * max(b for b, _ in big):.2f} % → "
            f"{100 * max(a for _, a in big):.2f} % | {worse} | {o['inserted_vertices']} ({o['interface_splits']}) | "
            f"{o['removed_vertices']} | {o['seconds'] / rest:.2f} | {user_plain:.2f} → {user_opt:.2f} |")


def main():
    argv = sys.argv[1:]
    spacings = [1.0, 2.0]
    if "--spacings" in argv:
        i = argv.index("--spacings")
        spacings = [float(s) for s in argv[i + 1].split(",")]
        del argv[i:i + 2]
    exe, slices = argv[0], argv[1:]
    print("| slice, spacing | min angle before → after | max angle before → after | mean min after | "
          "Σ\\|area − pixel area\\| / Σ pixel area before → after | worst label ≥ 500 px before → after | "
          "labels worse | inserted (on interfaces) | removed | optimise / meshing (report) | "
          "user s plain → --optimize |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for path in slices:
            for spacing in spacings:
                for graded in (False, True):
                    print(row(exe, path, spacing, graded, tmp), flush=True)


if __name__ == "__main__":
    main()
