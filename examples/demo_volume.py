#!/usr/bin/env python3
"""Write a small label volume (NIfTI-1 or NRRD) from a bundled atlas slice.

    /usr/bin/python3 examples/demo_volume.py seg.nii.gz
    /usr/bin/python3 examples/demo_volume.py seg.nrrd --slices 5 --voxel 0.9375,0.9375,1.5

warpmesh bundles 2D slices only (mesher/examples/*.pgm); the documentation's
volume examples mesh this script's output, so they run as written on a fresh
clone.  The volume is the slice repeated --slices times along k (int16 labels),
with the voxel size --voxel in mm (i, j, k), axis-aligned (an sform / space
directions diagonal in the voxel sizes, origin 0), like a segmentation exported
by 3D Slicer or ITK-SNAP.  The extension chooses the format: .nii, .nii.gz
(NIfTI-1, single file) or .nrrd (attached header, gzip encoding).  Needs only
numpy.
"""

import argparse
import gzip
import pathlib
import struct

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
DEFAULT_SLICE = HERE.parent / "mesher" / "examples" / "brain_axial_s128_labels16.pgm"


def read_pgm(path):
    """A binary PGM (P5, 8- or 16-bit) as a 2D array, row 0 at the top."""
    data = pathlib.Path(path).read_bytes()
    fields, pos = [], 2
    if data[:2] != b"P5":
        raise SystemExit(f"{path}: not a binary PGM (P5)")
    while len(fields) < 3:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos)
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(int(data[pos:end]))
        pos = end
    w, h, maxval = fields
    dtype = ">u2" if maxval > 255 else "u1"
    return np.frombuffer(data, dtype=dtype, count=w * h, offset=pos + 1).reshape(h, w)


def voxels(image, slices):
    """(i, j, k) array: i along columns, j up the image (warpmesh's PGM convention), k the copies."""
    upright = image[::-1, :].T.astype(np.int16)  # [i, j] with j = H-1-row
    return np.repeat(upright[:, :, None], slices, axis=2)


def write_nifti(path, vol, voxel):
    hdr = bytearray(348)
    struct.pack_into("<i", hdr, 0, 348)                                    # sizeof_hdr
    struct.pack_into("<8h", hdr, 40, 3, *vol.shape, 1, 1, 1, 1)            # dim
    struct.pack_into("<hh", hdr, 70, 4, 16)                                # datatype int16, bitpix
    struct.pack_into("<8f", hdr, 76, 1.0, *voxel, 1, 1, 1, 1)              # pixdim (qfac 1)
    struct.pack_into("<f", hdr, 108, 352.0)                                # vox_offset
    struct.pack_into("<hh", hdr, 252, 0, 2)                                # qform_code, sform_code (aligned)
    struct.pack_into("<4f", hdr, 280, voxel[0], 0, 0, 0)                   # srow_x
    struct.pack_into("<4f", hdr, 296, 0, voxel[1], 0, 0)                   # srow_y
    struct.pack_into("<4f", hdr, 312, 0, 0, voxel[2], 0)                   # srow_z
    hdr[344:348] = b"n+1\0"
    body = bytes(hdr) + b"\0" * 4 + vol.astype("<i2").tobytes(order="F")  # i fastest
    opener = gzip.open if str(path).endswith(".gz") else open
    with opener(path, "wb") as f:
        f.write(body)


def write_nrrd(path, vol, voxel):
    header = (
        "NRRD0004\n"
        "type: int16\n"
        "dimension: 3\n"
        "space: left-posterior-superior\n"
        f"sizes: {vol.shape[0]} {vol.shape[1]} {vol.shape[2]}\n"
        f"space directions: ({voxel[0]},0,0) (0,{voxel[1]},0) (0,0,{voxel[2]})\n"
        "space origin: (0,0,0)\n"
        "endian: little\n"
        "encoding: gzip\n\n"
    )
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(gzip.compress(vol.astype("<i2").tobytes(order="F")))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("output", help="seg.nii, seg.nii.gz or seg.nrrd")
    p.add_argument("--from", dest="source", default=str(DEFAULT_SLICE), help="a label PGM (default: the brain slice)")
    p.add_argument("--slices", type=int, default=3, help="copies of the slice along k (default 3)")
    p.add_argument("--voxel", default="0.9375,0.9375,1.5", help="voxel size in mm, i,j,k")
    a = p.parse_args()
    voxel = [float(v) for v in a.voxel.split(",")]
    if len(voxel) != 3 or min(voxel) <= 0 or a.slices < 1:
        raise SystemExit("--voxel needs three positive sizes and --slices at least 1")
    vol = voxels(read_pgm(a.source), a.slices)
    if a.output.endswith((".nii", ".nii.gz")):
        write_nifti(a.output, vol, voxel)
    elif a.output.endswith(".nrrd"):
        write_nrrd(a.output, vol, voxel)
    else:
        raise SystemExit(f"{a.output}: the name must end in .nii, .nii.gz or .nrrd")
    print(f"wrote {a.output}: {vol.shape[0]} x {vol.shape[1]} x {vol.shape[2]} voxels of "
          f"{voxel[0]:g} x {voxel[1]:g} x {voxel[2]:g} mm, labels {int(vol.min())}..{int(vol.max())}")


if __name__ == "__main__":
    main()
