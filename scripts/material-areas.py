#!/usr/bin/env python3
"""Per-label area errors of `--materials all` meshes, and how they move when
the labels are renumbered (issue 28 item 4, docs/multi-material.md, "Label
numbers do not matter").

    scripts/material-areas.py build/mesher/warpmesh SLICE.pgm... [--spacing S]

For each slice, meshes it as it is and with its nonzero labels renumbered by
the order-reversing bijection (the k-th smallest label becomes the k-th
largest; 0, the background, stays), and prints one Markdown row: the labels,
sum |area - pixel_area| over the labels / their pixel area, the worst label of
>= 200 pixels, the labels without a triangle (with their original numbers),
and the largest change of a label's relative area error under the
renumbering, over all labels and over those of >= 200 pixels (0 when the mesh does not
depend on the label numbers)."""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np


def read_pgm(path):
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    w, h, maxval = int(fields[1]), int(fields[2]), int(fields[3])
    dtype = ">u2" if maxval > 255 else "u1"
    return np.frombuffer(data[pos + 1:], dtype=dtype, count=w * h).reshape(h, w).astype(np.int64)


def write_pgm(path, img):
    h, w = img.shape
    with open(path, "wb") as f:
        f.write(b"P5\n%d %d\n65535\n" % (w, h))
        f.write(img.astype(">u2").tobytes())


def errors(warpmesh, pgm, spacing, tmp):
    report = os.path.join(tmp, "r.json")
    subprocess.run([warpmesh, "mesh", pgm, "--materials", "all", "--spacing", str(spacing), "-o", os.path.join(tmp, "m.vtu"),
                    "--report", report, "--quiet"], check=True)
    with open(report) as f:
        mats = json.load(f)["materials"]
    return {m["tag"]: (m["area"], m["pixel_area"], m["triangles"]) for m in mats if m["tag"] != 0}


def main():
    args = sys.argv[1:]
    spacing = 1.0
    if "--spacing" in args:
        k = args.index("--spacing")
        spacing = float(args[k + 1])
        del args[k:k + 2]
    warpmesh, slices = args[0], args[1:]
    print("| slice | labels | Σ\\|area − pixel area\\| / pixel area | worst label ≥ 200 px | lost labels | lost after renumbering"
          " | largest change under renumbering: all labels / labels >= 200 px |")
    print("|---|---:|---:|---:|---|---|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for pgm in slices:
            img = read_pgm(pgm)
            labels = sorted(int(v) for v in np.unique(img) if v != 0)
            rev = dict(zip(labels, reversed(labels)))
            lut = np.arange(65536)
            for a, b in rev.items():
                lut[a] = b
            perm_pgm = os.path.join(tmp, "perm.pgm")
            write_pgm(perm_pgm, lut[img])
            e0 = errors(warpmesh, pgm, spacing, tmp)
            e1 = errors(warpmesh, perm_pgm, spacing, tmp)
            rel = lambda e, t: (e[t][0] - e[t][1]) / e[t][1]
            total = sum(abs(a - p) for a, p, _ in e0.values()) / sum(p for _, p, _ in e0.values())
            big = [t for t in labels if e0[t][1] >= 200]
            worst = max(big, key=lambda t: abs(rel(e0, t)))
            lost0 = [t for t in labels if e0[t][2] == 0]
            lost1 = [t for t in labels if e1[rev[t]][2] == 0]
            change = max(abs(rel(e0, t) - rel(e1, rev[t])) for t in labels)
            change_big = max(abs(rel(e0, t) - rel(e1, rev[t])) for t in big)
            name = os.path.basename(pgm).replace("_labels16.pgm", "")
            print(f"| {name} | {len(labels)} | {100 * total:.2f} % | {100 * rel(e0, worst):+.2f} % (label {worst}) | "
                  f"{', '.join(map(str, lost0)) or '–'} | {', '.join(map(str, lost1)) or '–'} | {100 * change:.1f} / {100 * change_big:.1f} points |")


if __name__ == "__main__":
    main()
