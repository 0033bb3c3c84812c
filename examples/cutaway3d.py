"""A cut-away picture of a tetrahedral mesh, each tetrahedron coloured by its
minimum dihedral angle: what docs/brain3d_cutaway.png shows.  Pure numpy (an
orthographic z-buffer rasteriser with flat shading) and zlib, so it needs no
display and no plotting library.

    warpmesh mesh3d hncma-atlas.nrrd --label nonzero --spacing 3 -o brain.vtu
    python3 examples/cutaway3d.py brain.vtu docs/brain3d_cutaway.png

The octant of the mesh facing the viewer (x above, y below, z above the
centre of its bounding box) is removed, tetrahedra whole, so the cut shows
the interior tetrahedra as they are.  Colour: minimum dihedral angle over
0°–70° (red … yellow … green), grey edges where the triangles are wide
enough; a colour bar with its end values on the right.
"""
import struct
import sys
import zlib

import numpy as np

# Each face of a positively oriented tetrahedron, oriented outwards.
FACES = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]])


def min_dihedral_deg(p, t):
    """The smallest of the six dihedral angles of each tetrahedron (degrees)."""
    x = p[t]                                     # (T, 4, 3)
    # Face normals (outward); the dihedral at an edge is π − the angle between
    # the outward normals of its two faces.
    n = np.stack([np.cross(x[:, f[1]] - x[:, f[0]], x[:, f[2]] - x[:, f[0]]) for f in FACES], axis=1)
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    best = np.full(len(t), 180.0)
    for i in range(4):
        for j in range(i + 1, 4):
            c = np.clip(np.einsum("ij,ij->i", n[:, i], n[:, j]), -1, 1)
            best = np.minimum(best, 180 - np.degrees(np.arccos(c)))
    return best


def surface_of(t, keep):
    """The faces of the kept tetrahedra that belong to one of them, oriented
    outwards, with the index of that tetrahedron."""
    idx = np.flatnonzero(keep)
    faces = t[idx][:, FACES].reshape(-1, 3)
    owner = np.repeat(idx, 4)
    key = np.sort(faces, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    once = counts[inverse.ravel()] == 1
    return faces[once], owner[once]


def colour(v, lo=0.0, hi=70.0):
    """Red (lo) → yellow → green (hi), as float RGB in [0, 1]."""
    s = np.clip((v - lo) / (hi - lo), 0, 1)[..., None]
    red, yellow, green = np.array([0.85, 0.1, 0.1]), np.array([0.95, 0.85, 0.2]), np.array([0.15, 0.65, 0.3])
    return np.where(s < 0.5, red + (yellow - red) * (2 * s), yellow + (green - yellow) * (2 * s - 1))


DIGITS = {  # 3 x 5 bitmap digits and the degree sign, rows top to bottom
    "0": ["111", "101", "101", "101", "111"], "1": ["010", "110", "010", "010", "111"],
    "2": ["111", "001", "111", "100", "111"], "3": ["111", "001", "111", "001", "111"],
    "4": ["101", "101", "111", "001", "001"], "5": ["111", "100", "111", "001", "111"],
    "6": ["111", "100", "111", "101", "111"], "7": ["111", "001", "010", "010", "010"],
    "8": ["111", "101", "111", "101", "111"], "9": ["111", "101", "111", "001", "111"],
    "°": ["111", "101", "111", "000", "000"],
}


def text(img, s, x, y, scale=3):
    for ch in s:
        for r, row in enumerate(DIGITS[ch]):
            for c, bit in enumerate(row):
                if bit == "1":
                    img[y + r * scale:y + (r + 1) * scale, x + c * scale:x + (c + 1) * scale] = 0.15
        x += 4 * scale


def render(p, faces, values, width=820, height=640, ss=2):
    view = np.array([1.0, -1.3, 0.9])
    view /= np.linalg.norm(view)
    right = np.cross([0, 0, 1.0], view)
    right /= np.linalg.norm(right)
    up = np.cross(view, right)
    q = np.stack([p @ right, p @ up, p @ view], axis=1)  # depth: larger = nearer the viewer
    lo, hi = q[:, :2].min(axis=0), q[:, :2].max(axis=0)
    W, H = width * ss, height * ss
    scale = 0.92 * min(W / (hi[0] - lo[0]), H / (hi[1] - lo[1]))
    xy = (q[:, :2] - (lo + hi) / 2) * scale + [W / 2, H / 2]
    xy[:, 1] = H - xy[:, 1]
    depth = np.full((H, W), -np.inf)
    img = np.ones((H, W, 3))
    light = view + 0.6 * up - 0.3 * right
    light /= np.linalg.norm(light)
    n = np.cross(p[faces[:, 1]] - p[faces[:, 0]], p[faces[:, 2]] - p[faces[:, 0]])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    front = n @ view > 0
    shade = 0.35 + 0.65 * np.abs(n @ light)
    rgb = colour(values) * shade[:, None]
    for k in np.flatnonzero(front):
        a, b, c = xy[faces[k]]
        x0, x1 = int(max(0, np.floor(min(a[0], b[0], c[0])))), int(min(W - 1, np.ceil(max(a[0], b[0], c[0]))))
        y0, y1 = int(max(0, np.floor(min(a[1], b[1], c[1])))), int(min(H - 1, np.ceil(max(a[1], b[1], c[1]))))
        if x1 < x0 or y1 < y0:
            continue
        gy, gx = np.mgrid[y0:y1 + 1, x0:x1 + 1] + 0.5
        den = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1])
        if den == 0:
            continue
        l0 = ((b[1] - c[1]) * (gx - c[0]) + (c[0] - b[0]) * (gy - c[1])) / den
        l1 = ((c[1] - a[1]) * (gx - c[0]) + (a[0] - c[0]) * (gy - c[1])) / den
        l2 = 1 - l0 - l1
        inside = (l0 >= 0) & (l1 >= 0) & (l2 >= 0)
        z = l0 * q[faces[k, 0], 2] + l1 * q[faces[k, 1], 2] + l2 * q[faces[k, 2], 2]
        win = inside & (z > depth[y0:y1 + 1, x0:x1 + 1])
        if not win.any():
            continue
        depth[y0:y1 + 1, x0:x1 + 1][win] = z[win]
        # Edges: darker within about a pixel of a side (in picture pixels).
        heights = [abs(den) / np.hypot(*(b - c)), abs(den) / np.hypot(*(c - a)), abs(den) / np.hypot(*(a - b))]
        edge = np.minimum(np.minimum(l0 * heights[0], l1 * heights[1]), l2 * heights[2]) < 0.6 * ss
        px = np.where(edge[..., None], rgb[k] * 0.7, rgb[k])
        img[y0:y1 + 1, x0:x1 + 1][win] = px[win]
    img = img.reshape(height, ss, width, ss, 3).mean(axis=(1, 3))
    # Colour bar on the right.
    bar = np.ones((height, 110, 3))
    ys = np.arange(60, height - 60)
    bar[60:height - 60, 30:55] = colour(70 * (1 - (ys - 60) / (len(ys) - 1)))[:, None, :]
    text(bar, "70°", 60, 55)
    text(bar, "0°", 60, height - 75)
    return np.concatenate([img, bar], axis=1)


def write_png(path, img, levels=32):
    """An 8-bit RGB PNG, each channel rounded to `levels` values (smaller files)."""
    step = 255 / (levels - 1)
    a = (np.round(np.clip(img, 0, 1) * 255 / step) * step + 0.5).astype(np.uint8)
    h, w, _ = a.shape
    raw = b"".join(b"\x00" + a[r].tobytes() for r in range(h))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main(src, dst):
    import meshio

    m = meshio.read(src)
    p, t = m.points, m.cells_dict["tetra"]
    angle = min_dihedral_deg(p, t)
    centroid = p[t].mean(axis=1)
    c = (p.min(axis=0) + p.max(axis=0)) / 2
    keep = ~((centroid[:, 0] > c[0]) & (centroid[:, 1] < c[1]) & (centroid[:, 2] > c[2]))
    faces, owner = surface_of(t, keep)
    write_png(dst, render(p, faces, angle[owner]))
    print(f"{len(t)} tetrahedra, min dihedral {angle.min():.2f} deg; {len(faces)} faces drawn -> {dst}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
