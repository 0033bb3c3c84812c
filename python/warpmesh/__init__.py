"""warpmesh — conforming triangle meshes of 2D level sets by lattice warping,
with certified angle bounds.

    >>> import numpy as np, warpmesh
    >>> image = np.zeros((64, 64), np.uint8); image[16:48, 20:40] = 200
    >>> m = warpmesh.mesh(image)                      # threshold at maxval / 2
    >>> m.points.shape, m.triangles.shape             # (n, 2) float64, (t, 3) int32
    >>> m.report["certified"]["min_angle_deg"]        # every angle is at least this
    >>> m.to_meshio().write("mesh.vtu")

    >>> d = warpmesh.mesh_shape("circle:0,0,1", spacing=0.05, graded=True)

    >>> t = warpmesh.mesh3d(labels_zyx, label="nonzero", voxel_size=(1, 1, 1.5))
    >>> t.points.shape, t.tetrahedra.shape            # (n, 3) float64, (t, 4) int32
    >>> a = warpmesh.mesh3d(labels_zyx, materials="all")  # every label, one mesh
    >>> a.regions, a.interfaces, a.interface_regions  # label per tetrahedron, shared faces

The functions release the GIL while meshing (threads can mesh in parallel; the
mesher itself uses OpenMP threads, `threads=` per call).  Every bad input
(an argument of the wrong type or value, an image warpmesh cannot mesh, a
file it cannot read) raises warpmesh.InputError, a subclass of ValueError; an
output that cannot be written raises OSError (warpmesh.OutputError).
"""
import json
import os
import warnings

import numpy as np

from . import _core
from ._core import InputError, OptionError, OutputError, png_supported, certified_table_available

__all__ = ["mesh", "mesh_shape", "mesh_shapes", "mesh3d", "lattice3d", "mesh3d_block", "merge_blocks", "block_voxels", "mesh3d_block_read",
           "region_part_voxels", "region_part_facts", "region_part_facts_read", "merge_region_facts",
           "write_blocks", "write_block", "write_pvtu",
           "read_image", "read_volume",
           "Volume",
           "write", "Mesh", "TetMesh", "Image", "InputError", "OptionError", "OutputError", "png_supported",
           "certified_table_available"]

# The CLI's --max-squares and --max-pixels defaults.
_MAX_SQUARES = 1 << 30
_MAX_PIXELS = 1 << 28
_MAX_MEMORY_MB = 2048  # the CLI's --max-memory default


class Image(np.ndarray):
    """A 2D uint16 array of samples (row 0 at the top) as read from a file, with
    ``maxval`` (the file's largest possible sample: the default threshold is
    half of it), ``source`` (the path) and where its pixels lie:

      units      "mm" or "pixels"
      geometry   (x0, y0, sx, sy) in millimetres: the pixel in column c and
                 row r is centred at (x0 + c sx, y0 + (rows - 1 - r) sy); None
                 in pixel units.  mesh() meshes such an image in millimetres.
      plane      where the slice's 2D point (x, y) lies in 3D: origin + x
                 x_axis + y y_axis (a dict of "origin", "x_axis", "y_axis",
                 "normal"; None for a plain image)."""

    def __new__(cls, pixels, maxval, source="", placement=None):
        obj = np.asarray(pixels).view(cls)
        obj.maxval = int(maxval)
        obj.source = str(source)
        placement = placement or {}
        obj.units = placement.get("units", "pixels")
        obj.geometry = tuple(placement["geometry"]) if obj.units == "mm" else None
        obj.plane = {k: tuple(placement[k]) for k in ("origin", "x_axis", "y_axis", "normal")} if placement else None
        return obj

    def __array_finalize__(self, obj):
        self.maxval = getattr(obj, "maxval", None)
        self.source = getattr(obj, "source", "")
        # A view keeps the placement only if it has all the pixels.
        same = obj is not None and getattr(obj, "shape", None) == self.shape
        self.units = getattr(obj, "units", "pixels") if same else "pixels"
        self.geometry = getattr(obj, "geometry", None) if same else None
        self.plane = getattr(obj, "plane", None) if same else None


def _max_memory(mb):
    """max_memory= in megabytes (as the CLI's --max-memory) -> bytes."""
    return _integer("max_memory", mb, 1) << 20


def read_image(path, *, slice=None, units=None, max_pixels=_MAX_PIXELS, max_memory=_MAX_MEMORY_MB):
    """Read an image, or one slice of a volume, the way the CLI reads it: PGM
    (P2/P5, 8 or 16 bits), PNG (when built with libpng), NRRD, NIfTI-1/2 and
    TIFF, recognised by content.

    ``slice`` ("k=60"; axis i, j or k, as the CLI's --slice) is required for a
    volume of more than one slice.  The rows and columns are the slice as the
    CLI meshes it: its first in-plane index axis along the columns, its second
    upwards (row 0 at the top).  Samples must be integers in 0..65535 (label
    maps, 8/16-bit images); anything else is refused.

    ``units`` as the CLI's --units: None (default) gives millimetres when the
    file has a physical geometry (NRRD, NIfTI) and pixels otherwise; "mm" or
    "pixels" choose.  In millimetres the Image's ``geometry`` holds the pixel
    sizes (anisotropic pixels are fine) and the origin, and mesh() meshes it
    there: the points are the CLI's `--slice ... --units mm` points.

    Returns an Image (a numpy uint16 array of shape (rows, columns) owning the
    samples, no copy) with ``maxval``, ``source``, ``units``, ``geometry``
    and ``plane``.  ``max_memory`` (megabytes, as the CLI's --max-memory)
    refuses, before reading, a file whose samples would not fit.  Raises
    InputError naming the file and the problem."""
    if units not in (None, "mm", "pixels"):
        raise InputError(f"units must be None, 'mm' or 'pixels', got {units!r}")
    pixels, maxval, placement = _core.read_image(str(path), None if slice is None else str(slice), units,
                                                 _integer("max_pixels", max_pixels, 1), _max_memory(max_memory))
    return Image(pixels, maxval, path, placement)


class Volume:
    """A volume as read_volume() reads it (the CLI's reader): the samples and
    where its voxels lie.

      data        (nz, ny, nx) float64 array owning the samples: voxel (i, j, k)
                  is data[k, j, i] (also np.asarray(volume))
      spacing     (si, sj, sk) the voxel sizes along the index axes i, j, k
                  (mm when physical, else 1)
      origin      (x, y, z) of voxel (0, 0, 0)
      direction   3x3 array whose column a is the unit direction of index axis
                  a (ITK's direction matrix; only signed permutations: the
                  readers refuse oblique volumes)
      affine      4x4 voxel-to-world matrix: (x, y, z, 1) = affine @ (i, j, k, 1)
      units       "mm" (physical: the file gives a voxel size) or "pixels"
      integer_valued, format ("NRRD", "NIfTI-1", "TIFF", ...), source (the
      path), warnings (what the reader accepted but says)

    mesh3d(volume, ...) meshes it where the CLI meshes the file: the same
    points and tetrahedra."""

    def __init__(self, data, geometry):
        self.data = data
        self._geometry = dict(geometry)
        g = self._geometry
        self.spacing = tuple(float(x) for x in g["spacing"])
        self.origin = tuple(float(x) for x in g["origin"])
        self.direction = np.array(g["axes"], dtype=float).T
        self.units = "mm" if g["physical"] else "pixels"
        self.physical = bool(g["physical"])
        self.integer_valued = bool(g["integer_valued"])
        self.format, self.source, self.warnings = g["format"], g["source"], list(g["warnings"])

    @property
    def affine(self):
        a = np.eye(4)
        a[:3, :3] = self.direction * np.asarray(self.spacing)
        a[:3, 3] = self.origin
        return a

    shape = property(lambda self: self.data.shape)
    dtype = property(lambda self: self.data.dtype)

    def __array__(self, dtype=None, copy=None):
        return self.data if dtype is None else self.data.astype(dtype)

    def __repr__(self):
        nz, ny, nx = self.data.shape
        return (f"<warpmesh.Volume {nx} x {ny} x {nz} voxels of {self.spacing} {self.units}, {self.format} "
                f"'{self.source}'>")


def read_volume(path, *, max_voxels=_MAX_PIXELS, max_memory=_MAX_MEMORY_MB):
    """Read a volume the way the CLI's mesh3d reads it: NRRD (.nrrd, .nhdr),
    NIfTI-1/2 (.nii, .nii.gz), multi-page TIFF (and PGM/PNG as one slice),
    recognised by content.  Returns a Volume: the samples as a float64 numpy
    array (z, y, x) with the voxel-to-world matrix (affine), spacing, origin
    and direction.  mesh3d(read_volume(path), ...) gives the CLI's mesh of
    the file.  max_voxels and max_memory (megabytes) refuse, before reading,
    a volume that would not fit (the CLI's --max-pixels, --max-memory).
    Raises InputError naming the file and the problem."""
    data, geometry = _core.read_volume(os.fspath(path), _integer("max_voxels", max_voxels, 1), _max_memory(max_memory))
    return Volume(data, geometry)


class Mesh:
    """The result of mesh() / mesh_shape().

    Arrays (numpy views of the C++ mesh, read-only, kept alive by this object):
      points            (n, 2) float64   vertex coordinates (pixel units × pixel_size, or
                                         millimetres for an Image read_image placed in mm)
      triangles         (t, 3) int32     counter-clockwise vertex indices
      regions           (t,)   int32     region tag per triangle (label images: the label; else 1)
      boundary_edges    (b, 2) int32     edges of one triangle, region on the left
      boundary_tags     (b,)   int32     1 = on the level set, 2 = on the domain border
      certified_min_angle (t,) float64   certified lower bound of the triangle's angles,
                                         degrees (None without certification)
      interfaces        (k, 2) int32     edges between two regions (multi-material; else empty)
      interface_regions (k, 2) int32     their (left, right) regions
    Other attributes: report (dict, the CLI's --report JSON), warnings (list of
    str, also issued as Python warnings), spacing (final lattice spacing),
    refinements (halvings made by guarantee="flat").
    """

    def __init__(self, core, pixel_size=None):
        self._core = core
        self._scale = pixel_size
        self.report = json.loads(core.to_json())
        self.warnings = list(core.warnings)
        self.spacing = core.spacing * (pixel_size or 1.0)
        self.refinements = core.refinements

    @property
    def points(self):
        p = self._core.points
        return p if self._scale is None else p * self._scale

    triangles = property(lambda self: self._core.triangles)
    regions = property(lambda self: self._core.regions)
    boundary_edges = property(lambda self: self._core.boundary_edges)
    boundary_tags = property(lambda self: self._core.boundary_tags)
    interfaces = property(lambda self: self._core.interfaces)
    interface_regions = property(lambda self: self._core.interface_regions)
    region_names = property(lambda self: dict(self._core.region_names))

    @property
    def certified_min_angle(self):
        return self._core.cell_data.get("certified_min_angle")

    @property
    def certified(self):
        """The certified angle interval [min, max] in degrees of every triangle
        (None without certification)."""
        c = self.report.get("certified")
        return None if c is None else (c["min_angle_deg"], c["max_angle_deg"])

    def to_text(self):
        """The CLI's text report."""
        return self._core.to_text()

    def write(self, path, *, ascii=False, compress=False, xdmf_inline=False):
        """Write the mesh with warpmesh's own writers, chosen by extension:
        .vtu, .msh, .xdmf, .inp, .node/.ele, .svg, .png (atomic; in the mesher's
        units: pixels before pixel_size, or millimetres for an Image placed in
        mm); see write()."""
        self._core.write(str(path), ascii, compress, xdmf_inline)

    def to_meshio(self, boundary=False):
        """A meshio.Mesh: the triangles with cell data "region" (int32) and,
        when certified, "certified_min_angle" (float64).  With boundary=True a
        "line" block of the boundary edges follows, its "region" the boundary
        tags (certified_min_angle NaN there)."""
        import meshio

        cells = [("triangle", self.triangles)]
        region = [self.regions]
        cma = self.certified_min_angle
        angle = [cma] if cma is not None else None
        if boundary:
            cells.append(("line", self.boundary_edges))
            region.append(self.boundary_tags)
            if angle is not None:
                angle.append(np.full(len(self.boundary_edges), np.nan))
        cell_data = {"region": region}
        if angle is not None:
            cell_data["certified_min_angle"] = angle
        return meshio.Mesh(self.points, cells, cell_data=cell_data)

    def __repr__(self):
        c = self.certified
        cert = "" if c is None else f", certified angles [{c[0]:.4g}, {c[1]:.4g}] deg"
        return f"<warpmesh.Mesh {len(self.points)} points, {len(self.triangles)} triangles{cert}>"


def _number(name, value, low=None):
    """A finite float (at least `low`), else InputError."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not np.isfinite(v) or (low is not None and v < low):
        raise InputError(f"{name} must be a finite number{'' if low is None else f' >= {low}'}, got {value!r}")
    return v


def _integer(name, value, low=None):
    """An int (integral numbers only, at least `low`), else InputError."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer, float, np.floating)) \
            or value != np.floor(value) or not np.isfinite(value):
        raise InputError(f"{name} must be an integer, got {value!r}")
    if low is not None and value < low:
        raise InputError(f"{name} must be at least {low}, got {value!r}")
    return int(value)


def _choice(name, value, choices):
    if not isinstance(value, str) or value not in choices:
        raise InputError(f"{name} must be " + ", ".join(repr(c) for c in choices[:-1]) +
                         f" or {choices[-1]!r}, got {value!r}")
    return value


def write(result, path, *, ascii=False, compress=False, xdmf_inline=False):
    """Writes `result` (a Mesh) to `path` with the CLI's writers, the format
    chosen by the extension: .vtu (appended raw binary; zlib with
    compress=True), .msh (Gmsh 4.1 binary), .xdmf (+ _facets.xdmf, heavy data
    in .h5 files beside them; inline XML with xdmf_inline=True), .inp,
    .node/.ele, .svg, .png.  ascii=True writes every format as text.  The
    files appear complete or not at all; failures raise OutputError."""
    result.write(path, ascii=ascii, compress=compress, xdmf_inline=xdmf_inline)


# The library's option tables (pipeline/options.hpp): per option its name (the
# keyword), kind, metavar, choices, help group, help (options named as
# keywords) and the CLI's flag.  The functions below pass the keywords of
# these tables to the library, which parses and validates them (OptionError,
# a subclass of InputError, naming the keyword).
_OPTIONS2D = _core.option_table("mesh2d")
_OPTIONS3D = _core.option_table("mesh3d")
_MISSING = object()


def _same(a, b):
    """Whether a keyword's value is its default (bools only equal bools)."""
    if a is b:
        return True
    if isinstance(a, (bool, np.bool_)) != isinstance(b, (bool, np.bool_)):
        return False
    try:
        return bool(a == b)
    except Exception:
        return False


def _given(table, function, values):
    """The table's keywords among `values` (a call's locals()) that differ from
    `function`'s defaults: a keyword left at its default is as if not given
    (None where the default is not None is given: the library refuses it)."""
    defaults = function.__kwdefaults__
    names = {o["name"] for o in table}
    return {k: v for k, v in values.items() if k in names and not _same(v, defaults.get(k, _MISSING))}


def _options_doc(table, skip=()):
    """The docstring lines of a table's keywords: name, then its help."""
    import textwrap

    lines = []
    for o in table:
        if o["name"] in skip:
            continue
        value = " or ".join(repr(c) for c in o["choices"]) if o["choices"] else o["metavar"]
        text = (f"{value}: " if value else "") + o["help"] + f" (the CLI's {o['flag']})"
        lines += textwrap.wrap(text, 79, initial_indent=f"    {o['name']:<11} ", subsequent_indent=" " * 16,
                               break_on_hyphens=False)
    return "\n".join(lines)


def _threads(threads):
    return None if threads is None else _integer("threads", threads, 1)


def _pixel_size(pixel_size):
    if pixel_size is None:
        return None
    try:
        s = np.broadcast_to(np.asarray(pixel_size, dtype=float), (2,))
    except (TypeError, ValueError):
        s = None
    if s is None or s[0] != s[1] or not (s[0] > 0) or not np.isfinite(s[0]):
        raise InputError(f"pixel_size must be one positive number (square pixels), got {pixel_size!r}"
                         " (anisotropic pixels: read_image a NRRD/NIfTI file, whose pixel sizes mesh() uses)")
    return float(s[0])


def _finish(core, pixel_size=None):
    m = Mesh(core, pixel_size)
    for w in m.warnings:
        warnings.warn("warpmesh: " + w, RuntimeWarning, stacklevel=3)
    return m


def _label_value(v):
    return _integer("label", v, 0)


def _labels(labels):
    """labels= → (list of ints or None, nonzero)."""
    if labels is None:
        return None, False
    if isinstance(labels, str):
        if labels == "nonzero":
            return None, True
        out = []
        for part in labels.split(","):
            lo, _, hi = part.strip().partition("-")
            try:
                out.extend(range(int(lo), int(hi or lo) + 1))
            except ValueError:
                raise InputError(f"bad label list {labels!r}: expected e.g. 3, \"51,52\", \"1-9\" or \"nonzero\"") \
                    from None
        return out, False
    if np.isscalar(labels):
        return [_label_value(labels)], False
    try:
        return [_label_value(v) for v in labels], False
    except TypeError:
        raise InputError(f"labels must be an int, a list of ints or a string, got {labels!r}") from None


def _pixels(image):
    """The image as a 2D array and its default maxval, or InputError."""
    try:
        a = np.asarray(image)
    except Exception as e:  # e.g. ragged nested lists
        raise InputError(f"the image must be a 2D array: {e}") from None
    if a.ndim != 2:
        raise InputError(f"the image must be 2D (rows, columns), got shape {a.shape}")
    if a.dtype == bool:
        maxval = 1
    elif np.issubdtype(a.dtype, np.integer):
        if a.size and (a.min() < 0 or a.max() > 65535):
            raise InputError("image values must lie in 0..65535")
        maxval = {np.dtype(np.uint8): 255, np.dtype(np.uint16): 65535}.get(a.dtype, int(a.max(initial=0)))
    else:
        raise InputError(f"image dtype {a.dtype} is not supported: give integers in 0..65535 or booleans "
                         "(e.g. (img * 255).astype(np.uint8) for a float image in [0, 1])")
    return a, getattr(image, "maxval", None) or max(maxval, 1)


def mesh(image, *, iso=None, inside="above", labels=None, materials=None, background="drop", spacing=None,
         pixel_size=None, graded=False, max_cell=0, max_size=None, grading=2.0, max_size_of=None, rule=None,
         lattice="square", guarantee=None, min_spacing=None, certify=True, verify=True, max_squares=_MAX_SQUARES,
         threads=None, optimize=False, max_memory=_MAX_MEMORY_MB, repeat=1):
    """Mesh a 2D image (numpy array, row 0 at the top), as ``warpmesh mesh`` does.

    image       2D array of integers in 0..65535 or booleans (a uint8 image from
                scikit-image, a label map, an Image from read_image)
    iso         threshold mode: the region is where the bilinear image is above
                iso (inside="above") or below it (inside="below").  Default:
                half of maxval — image.maxval for an Image, 255 for uint8,
                1 for bool, 65535 for uint16 arrays, else the array's maximum
    labels      label mode instead: an int, a list of ints, "51,52", "1-9" or
                "nonzero"; the region is the pixels with one of these labels,
                triangles are tagged with the nearest pixel's label
    materials   multi-material instead: "all" (every label but 0) or a list of
                labels, meshed together in one conforming mesh, regions = the
                labels, interfaces between them as edges (Mesh.interfaces); the
                other pixels are the background (tag 0), whose triangles are
                kept only with background="keep".  Uniform or graded (the finest
                band follows every interface); every rule but maxmin
    spacing     lattice spacing in the image's units: pixels (default 1), or
                millimetres for an Image read_image placed in mm (default its
                smaller pixel size; anisotropic pixels are meshed as the CLI
                meshes them)
    pixel_size  scales the output coordinates of an image in pixels (square
                pixels: angles and bounds are unchanged)
    threads     OpenMP threads for this call (default: all cores)

    The options (the library's table, as the CLI's; a keyword left at its
    default is as if not given):
%(options)s

    Returns a Mesh.  Raises InputError (a ValueError) for every bad input:
    an argument of the wrong type or value (OptionError, naming the keyword),
    an empty region, a lattice over max_squares, labels absent from the image, ...
    """
    a, maxval = _pixels(image)
    _choice("inside", inside, ("above", "below"))
    if labels is not None and iso is not None:
        raise InputError("iso (threshold mode) and labels (label mode) exclude each other")
    geometry = getattr(image, "geometry", None)
    if geometry is not None and pixel_size is not None:
        raise InputError("pixel_size scales an image in pixels; this Image is placed in millimetres by read_image "
                         "(read it with units=\"pixels\" to scale it yourself)")
    scale = _pixel_size(pixel_size)
    if spacing is None:
        spacing = 1.0 if geometry is None else min(geometry[2], geometry[3])
    source = getattr(image, "source", "") or "<array>"
    threads = _threads(threads)
    options = dict(_given(_OPTIONS2D, mesh, locals()), input=source)
    if materials is not None:
        if labels is not None or iso is not None:
            raise InputError("materials (multi-material mode) excludes iso and labels")
        spec = materials if isinstance(materials, str) else \
            ",".join(str(_label_value(m)) for m in np.atleast_1d(np.asarray(materials, dtype=object)))
        core = _core.mesh_materials(a.astype(np.uint16, copy=False), int(maxval), spec, source, geometry, threads,
                                    options)
        return _finish(core, scale)
    label_list, nonzero = _labels(labels)
    core = _core.mesh_image(a.astype(np.uint16, copy=False), int(maxval),
                            None if iso is None else _number("iso", iso), inside == "above", label_list, nonzero,
                            source, geometry, threads, options)
    return _finish(core, scale)


def mesh_shape(spec, *, spacing=1.0, graded=False, max_cell=0, max_size=None, grading=2.0, rule=None,
               lattice="square", guarantee=None, min_spacing=None, certify=True, verify=True, max_squares=_MAX_SQUARES,
               threads=None, optimize=False, max_memory=_MAX_MEMORY_MB, repeat=1):
    """Mesh an analytic shape given as the CLI's --shape string:
    circle:cx,cy,r  ellipse:cx,cy,a,b  annulus:cx,cy,r1,r2  flower:cx,cy,a,b,k
    rect:x0,y0,x1,y1  union(S;S)  intersect(S;S)  diff(S;S).  Options as in
    mesh(); the report also gives the boundary fidelity."""
    if not isinstance(spec, str):
        raise InputError(f"the shape must be a string such as \"circle:0,0,1\", got {spec!r}")
    options = dict(_given(_OPTIONS2D, mesh_shape, locals()), input=spec)
    return _finish(_core.mesh_shape(spec, _threads(threads), options))


def mesh_shapes(spec, *, background="drop", spacing=1.0, graded=False, max_cell=0, max_size=None, grading=2.0,
                max_size_of=None, rule=None, lattice="square", guarantee=None, min_spacing=None, certify=True,
                verify=True, max_squares=_MAX_SQUARES, threads=None, optimize=False, max_memory=_MAX_MEMORY_MB,
                repeat=1):
    """Mesh analytic materials given as the CLI's --shapes string,
    "TAG=SHAPE;TAG=SHAPE;..." (e.g. "1=circle:0,0,10;2=circle:6,0,8"; a later
    shape wins where shapes overlap; outside them the background, tag 0, kept
    with background="keep"), in one conforming mesh whose regions are the tags
    and whose interfaces are mesh edges.  Options as in mesh() with materials
    (every rule but maxmin; guarantee="flat" and lattice="rhombic" do not
    apply)."""
    if not isinstance(spec, str):
        raise InputError(f"the shapes must be a string such as \"1=circle:0,0,1;2=circle:1,0,1\", got {spec!r}")
    options = dict(_given(_OPTIONS2D, mesh_shapes, locals()), input=spec)
    return _finish(_core.mesh_shapes(spec, _threads(threads), options))


if mesh.__doc__:  # (None under python -OO)
    mesh.__doc__ = mesh.__doc__ % {"options": _options_doc(_OPTIONS2D, skip=("spacing",))}


class TetMesh:
    """The result of mesh3d(): a tetrahedral mesh.

    Arrays (numpy views of the C++ mesh, read-only, kept alive by this object):
      points          (n, 3) float64   vertex coordinates (millimetres for a volume
                                       with voxel_size, else voxel units; a shape's units)
      tetrahedra      (t, 4) int32     vertex indices, every tetrahedron positively
                                       oriented: det(p1 - p0, p2 - p0, p3 - p0) > 0
      regions         (t,)   int32     region tag per tetrahedron (1; several
                                       materials: the material's tag, a label's value)
      boundary_faces  (b, 3) int32     the faces of one tetrahedron, normal
                                       (p1 - p0) x (p2 - p0) pointing out
      boundary_tags   (b,)   int32     1 = on the level set (or against the dropped
                                       background), 2 = where the volume's edge (the
                                       hull of its voxel centres) or the lattice's
                                       border cut the region off
      interfaces      (k, 3) int32     faces between two regions (several materials;
                                       else empty), normal pointing from
                                       interface_regions[:, 0] into [:, 1]
      interface_regions (k, 2) int32   those two regions' tags
    region_names (dict tag -> name, several materials: "label_41",
    "material_2", "background"), report (dict, the CLI's --report JSON:
    counts, measured and certified dihedral bounds, radius ratios, boundary
    fidelity; several materials: "materials", per material its tetrahedra,
    volume and voxels' volume, "interface_faces", "junctions"), warnings
    (list of str, also issued as Python warnings).
    """

    def __init__(self, core):
        self._core = core
        self.report = json.loads(core.to_json())
        self.warnings = list(core.warnings)

    points = property(lambda self: self._core.points)
    tetrahedra = property(lambda self: self._core.tetrahedra)
    regions = property(lambda self: self._core.regions)
    boundary_faces = property(lambda self: self._core.boundary_faces)
    boundary_tags = property(lambda self: self._core.boundary_tags)
    interfaces = property(lambda self: self._core.interfaces)
    interface_regions = property(lambda self: self._core.interface_regions)
    region_names = property(lambda self: dict(self._core.region_names))
    cell_data = property(lambda self: self._core.cell_data)

    @property
    def certified(self):
        """The certified dihedral interval [min, max] in degrees of the
        certified tetrahedra (report["certified"] counts the others), or None."""
        c = self.report.get("certified")
        return None if c is None else (c["min_dihedral_deg"], c["max_dihedral_deg"])

    def to_text(self):
        """The CLI's text report."""
        return self._core.to_text()

    def write(self, path, *, ascii=False, compress=False, xdmf_inline=False):
        """Write with warpmesh's writers, chosen by extension: .vtu, .msh,
        .xdmf (+ _facets.xdmf), .inp (C3D4), .mesh (medit); as write()."""
        self._core.write(str(path), ascii, compress, xdmf_inline)

    def to_meshio(self, boundary=False):
        """A meshio.Mesh: the tetrahedra with cell data "region" (int32).  With
        boundary=True a "triangle" block of the boundary faces follows, its
        "region" the boundary tags."""
        import meshio

        cells = [("tetra", self.tetrahedra)]
        region = [self.regions]
        if boundary:
            cells.append(("triangle", self.boundary_faces))
            region.append(self.boundary_tags)
        return meshio.Mesh(self.points, cells, cell_data={"region": region})

    def __repr__(self):
        c = self.certified
        cert = "" if c is None else f", certified dihedral angles [{c[0]:.4g}, {c[1]:.4g}] deg"
        return f"<warpmesh.TetMesh {len(self.points)} points, {len(self.tetrahedra)} tetrahedra{cert}>"


def _triple(name, value, positive):
    """Three finite numbers (x, y, z) from one or three, else InputError."""
    try:
        v = np.broadcast_to(np.asarray(value, dtype=float), (3,))
    except (TypeError, ValueError):
        v = None
    if v is None or not np.isfinite(v).all() or (positive and not (v > 0).all()):
        raise InputError(f"{name} must be one or three finite{' positive' if positive else ''} numbers (x, y, z), "
                         f"got {value!r}")
    return tuple(float(x) for x in v)


def _volume(volume):
    """The volume as a 3D array (z, y, x) and whether it is integer valued."""
    try:
        a = np.asarray(volume)
    except Exception as e:
        raise InputError(f"the volume must be a 3D array: {e}") from None
    if a.ndim != 3:
        raise InputError(f"the volume must be a 3D array (z, y, x), got shape {a.shape}")
    if a.dtype == bool:
        return a.astype(np.uint8), True
    if not (np.issubdtype(a.dtype, np.integer) or np.issubdtype(a.dtype, np.floating)):
        raise InputError(f"volume dtype {a.dtype} is not supported: give integers, floats or booleans")
    return a, bool(np.issubdtype(a.dtype, np.integer))


def _labels3(label, labels):
    """label= / labels= as the library's label list ("3", "51,52", "1-9",
    "nonzero"), or None."""
    if label is not None and labels is not None:
        raise InputError("label and labels are the same option: give one")
    label = labels if label is None else label
    if label is None or isinstance(label, str):
        return label
    if np.isscalar(label):
        return str(_label_value(label))
    try:
        return ",".join(str(_label_value(v)) for v in label)
    except TypeError:
        raise InputError(f"labels must be an int, a list of ints or a string, got {label!r}") from None


def _part(region, volume):
    """region=(start, shape) in numpy's (z, y, x) order as the library's
    part: (offset, whole dimensions) in (i, j, k) order."""
    try:
        start, whole = (tuple(_integer("region", v, 0) for v in t) for t in region)
    except (TypeError, ValueError):
        raise InputError(f"region must be (start, shape): the part's first voxel (z, y, x) in the whole volume and the "
                         f"whole's shape (nz, ny, nx), got {region!r}") from None
    if len(start) != 3 or len(whole) != 3:
        raise InputError(f"region must be (start, shape), each three integers (z, y, x), got {region!r}")
    if any(s + n > w for s, n, w in zip(start, np.shape(volume), whole)):
        raise InputError(f"the part (shape {np.shape(volume)} at {start}) does not lie in the whole volume of shape {whole}")
    return start[::-1], whole[::-1]


def _input3(volume, voxel_size, origin, options, shapes=None, region=None):
    """The pipeline's input: a shape string, material shapes (shapes=), a
    volume file (an os.PathLike path), or a numpy volume with its geometry
    (voxel_size, origin); a voxel_size given with a shape goes to the options
    (the library refuses it)."""
    size = None if voxel_size is None else _triple("voxel_size", voxel_size, True)
    if shapes is not None:
        if volume is not None:
            raise InputError("give a volume or shapes=, not both")
        if not isinstance(shapes, str):
            raise InputError(f"shapes must be a string such as \"1=sphere:0,0,0,1;2=sphere:0,0,0,0.5\", got {shapes!r}")
        volume = _core.MaterialShapes3(shapes)
    elif volume is None:
        raise InputError("give a volume (an array, a path or a shape string) or shapes=")
    elif isinstance(volume, os.PathLike) or (isinstance(volume, str) and os.path.isfile(volume)):
        volume = _core.VolumeFile(os.fspath(volume))
    if isinstance(volume, Volume):
        if tuple(origin) != (0.0, 0.0, 0.0):
            raise InputError("a Volume carries its origin (read_volume): give origin only with a numpy array")
        if size is not None:
            options["voxel_size"] = list(size)
        return _core.Volume3(volume.data, volume.integer_valued, None, (0.0, 0.0, 0.0), volume._geometry)
    if isinstance(volume, (str, _core.MaterialShapes3, _core.VolumeFile)):
        if size is not None:
            options["voxel_size"] = list(size)
        return volume
    a, integer_valued = _volume(volume)
    part = None if region is None else _part(region, a)
    return _core.Volume3(a, integer_valued, size, _triple("origin", origin, False), None, part)


def _options3(function, values, label, labels, iso, inside, threads=None, materials=None):
    """The library's options of a call: the table's keywords given (a call's
    locals(); the table converts and checks them, as the CLI's flags) and
    the input's, converted here (checked against the others by the library)."""
    o = _given(_OPTIONS3D, function, values)
    if materials is not None:
        if not isinstance(materials, str):
            materials = _labels3(materials, None)
        o["materials"] = materials
    label = _labels3(label, labels)
    if label is not None:
        o["labels"] = label
    if iso is not None:
        o["iso"] = _number("iso", iso)
    if inside is not None:
        o["inside"] = _choice("inside", inside, ("above", "below"))
    if threads is not None:
        o["threads"] = _threads(threads)
    return o


def mesh3d(volume=None, *, spacing=None, label=None, labels=None, iso=None, inside=None, materials=None, shapes=None,
           background="drop", voxel_size=None, origin=(0.0, 0.0, 0.0), box=None, face_rule=None, verify=False,
           band=None, graded=False, max_size=None, grading=2.0, manifold=False, max_memory=None, max_memory_mb=None,
           threads=None):
    """Tetrahedral mesh of a volume, a 3D shape or a function, as ``warpmesh
    mesh3d`` does (BCC lattice warping, dihedral angles certified by
    proofs/bcc_delaunay.cert for the default face rule, proofs/bcc.cert for
    parity); or of several materials in one conforming mesh (materials= of a
    label volume, shapes= of analytic materials).

    volume      one of
                * a 3D numpy array indexed (z, y, x), as SimpleITK's
                  GetArrayFromImage and tifffile give it: voxel (i, j, k) =
                  volume[k, j, i] lies at origin + (i sx, j sy, k sz);
                * a volume file as a path (a str naming a file,
                  pathlib.Path or another os.PathLike: NRRD, NIfTI,
                  multi-page TIFF, in mm when it gives a voxel size), as the
                  CLI's INPUT, or a Volume read_volume() read: the CLI's mesh
                  of the file (its direction matrix too);
                * a shape string as the CLI's --shape: sphere:cx,cy,cz,r
                  ellipsoid:cx,cy,cz,a,b,c  torus:cx,cy,cz,R,r
                  box:x0,y0,z0,x1,y1,z1  cylinder:x0,y0,z0,x1,y1,z1,r and
                  union/intersect/diff(S;S);
                * a callable f(x, y, z) -> float (f < 0 inside) with
                  box=(xmin, ymin, zmin, xmax, ymax, zmax) around the region
                  (evaluated point by point, one thread: for small meshes).
    label       label mode (volumes): an int, a list, "51,52", "1-9" or
                "nonzero"; the region is those voxels, f the signed distance
                between voxel centres, interpolated trilinearly.  (labels= is
                the same, as in mesh().)
    iso         threshold mode instead: inside where the trilinear volume is
                above iso (inside="above", the default) or below it
                (inside="below"); default the middle of the value range
    materials   several materials of a label volume in one mesh: "all" (every
                label but 0, the background) or labels (an int list or
                "3,41,42", "1000-1035"); every other voxel is the background.
                Each tetrahedron's region is its label (regions), the faces
                between two materials are listed (interfaces,
                interface_regions); report["materials"] gives each material's
                volume beside its voxels'.  Split by the parity face rule,
                certified by proofs/bcc.cert and, where three or four
                materials meet (junctions), proofs/bcc_junctions.cert.
    shapes      instead of volume: analytic materials as the CLI's --shapes,
                "1=sphere:0,0,0,1;2=sphere:0,0,0,0.5" (tag=shape; a later
                shape wins where they overlap; outside all: the background,
                tag 0); needs spacing
    voxel_size  (sx, sy, sz) in mm (one number: cubic voxels), origin the
                position of voxel (0, 0, 0); without voxel_size the volume is
                meshed in voxel units (a file: its own geometry)
    threads     OpenMP threads for this call (default: all cores)

    The options (the library's table, as the CLI's; max_memory_mb is
    max_memory's former name):
%(options)s

    Returns a TetMesh.  Raises InputError (a ValueError) for every bad input.
    Volumes too large for one machine: mesh3d_block and merge_blocks.
    """
    if max_memory_mb is not None:
        if max_memory is not None:
            raise InputError("max_memory_mb is max_memory's former name: give one of them")
        max_memory = max_memory_mb
    if callable(volume) and not isinstance(volume, str):
        if label is not None or labels is not None or iso is not None or voxel_size is not None or materials is not None:
            raise InputError("label, iso, voxel_size and materials apply to volumes (numpy arrays), not to shapes or "
                             "functions")
        if shapes is not None:
            raise InputError("give a function or shapes=, not both")
        options = _options3(mesh3d, locals(), None, None, None, inside)
        if box is None:
            raise InputError("a function needs box=(xmin, ymin, zmin, xmax, ymax, zmax) around its region")
        b = [_number("box", v) for v in np.asarray(box, dtype=object).ravel()]
        if len(b) != 6 or not all(b[k] < b[k + 3] for k in range(3)):
            raise InputError(f"box must be (xmin, ymin, zmin, xmax, ymax, zmax) with min < max, got {box!r}")
        core = _core.mesh3d_function(volume, b, options)
    else:
        if box is not None:
            raise InputError("box applies to a function, not to a volume or a shape")
        options = _options3(mesh3d, locals(), label, labels, iso, inside, threads, materials)
        core = _core.mesh3d(_input3(volume, voxel_size, origin, options, shapes), options)
    m = TetMesh(core)
    for w in m.warnings:
        warnings.warn("warpmesh: " + w, RuntimeWarning, stacklevel=2)
    return m


if mesh3d.__doc__:  # (None under python -OO)
    mesh3d.__doc__ = mesh3d.__doc__ % {"options": _options_doc(_OPTIONS3D)}


def lattice3d(volume=None, *, spacing=None, label=None, labels=None, iso=None, inside=None, materials=None, shapes=None,
              background="drop", voxel_size=None, origin=(0.0, 0.0, 0.0), band=None, region=None, region_facts=None):
    """The BCC lattice mesh3d uses for this input: its cubes (nx, ny, nz),
    to split into blocks [lo, hi) for mesh3d_block.  Arguments as mesh3d's
    (volumes, shape strings, materials= and shapes=); region and
    region_facts as mesh3d_block's (then any part will do: the lattice is
    the whole's)."""
    options = _options3(lattice3d, locals(), label, labels, iso, inside, materials=materials)
    return tuple(int(n) for n in _core.lattice3(_input3(volume, voxel_size, origin, options, shapes, region), options,
                                                region_facts))


def _box(name, box, shape):
    """(start, stop) in (z, y, x) order as the library's [lo, hi) in (i, j, k)."""
    try:
        start, stop = (tuple(_integer(name, v, 0) for v in t) for t in box)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be (start, stop), each three voxel indices (z, y, x), got {box!r}") from None
    if len(start) != 3 or len(stop) != 3:
        raise InputError(f"{name} must be (start, stop), each three voxel indices (z, y, x), got {box!r}")
    return start[::-1], stop[::-1]


def _zyx(box):
    return tuple(int(v) for v in box[0][::-1]), tuple(int(v) for v in box[1][::-1])


def _block_options_only(function, options):
    """Refuse keywords that are not mesh3d_block's (the region functions
    ignore its others, so that one dict of options serves the facts and
    the blocks)."""
    unknown = set(options) - set(mesh3d_block.__kwdefaults__)
    if unknown:
        raise TypeError(f"{function.__name__}() got unexpected keyword arguments {sorted(unknown)}")


def region_part_voxels(shape, start, stop, *, label=None, labels=None, band=None, voxel_size=None, **block_options):
    """One region of a label volume of `shape` (nz, ny, nx) meshed in blocks
    that read only their part (mesh3d_block's region=) needs the whole
    region's facts first: a reduction over parts that tile the volume.  The
    part owning the voxels [start, stop) (z, y, x) reads these voxels,
    (start, stop): its own and those their distance values depend on (about
    band + 2 voxels more along each axis, within the volume).  No voxel is
    read.  mesh3d_block's other options are ignored (one dict of options
    serves the facts and the blocks)."""
    _block_options_only(region_part_voxels, block_options)
    shape = tuple(_integer("shape", n, 2) for n in shape)
    options = _options3(region_part_voxels, locals(), label, labels, None, None)
    part = np.zeros((1, 1, 1), np.uint8)
    box = _core.region_part_voxels(_input3(part, voxel_size, (0.0, 0.0, 0.0), options, None, ((0, 0, 0), shape)),
                                   _box("start, stop", (start, stop), shape), options)
    return _zyx(box)


def region_part_facts(part, start, stop, *, region, label=None, labels=None, band=None, voxel_size=None,
                      **block_options):
    """The region's facts of the voxels [start, stop) (z, y, x) of a label
    volume: its voxel box, count, the distance field's minimum and depth
    there, and which labels occur (a small picklable dict).  `part` holds
    the voxels region_part_voxels names, region=(part_start, shape) as
    mesh3d_block's.  merge_region_facts combines the facts of parts that
    tile the volume; InputError if the part lacks voxels the facts depend
    on.  mesh3d_block's other options are ignored."""
    _block_options_only(region_part_facts, block_options)
    options = _options3(region_part_facts, locals(), label, labels, None, None)
    a = _input3(part, voxel_size, (0.0, 0.0, 0.0), options, None, region)
    return _core.region_part_facts(a, _box("start, stop", (start, stop), None), options)


def region_part_facts_read(read, shape, start, stop, **options):
    """region_part_facts of the voxels [start, stop) (z, y, x) of a label
    volume of `shape`, reading only the part they need: read(start, stop)
    returns volume[z0:z1, y0:y1, x0:x1] (as mesh3d_block_read's read).
    Options as region_part_facts'."""
    _block_options_only(region_part_facts_read, options)
    shape = tuple(int(n) for n in shape)
    part_start, part_stop = region_part_voxels(shape, start, stop, **options)
    return region_part_facts(read(part_start, part_stop), start, stop, region=(part_start, shape), **options)


def merge_region_facts(parts):
    """The whole region's facts from the facts of parts that tile the volume
    (region_part_facts, any order), for region_facts= of lattice3d,
    block_voxels, mesh3d_block and mesh3d_block_read.  Raises InputError,
    naming what is wrong, for parts that overlap, leave voxels out or were
    made with other labels, band or voxel size, and (as mesh3d) for an empty
    region or a listed label no voxel has."""
    parts = list(parts)
    return _core.merge_region_facts(parts)


def block_voxels(shape, lo, hi, *, halo=2, materials=None, label=None, labels=None, band=None, spacing=None,
                 background="drop", voxel_size=None, origin=(0.0, 0.0, 0.0), region_facts=None):
    """The voxels a block of a label volume of `shape` (nz, ny, nx) reads,
    as (start, stop) in (z, y, x) order: volume[z0:z1, y0:y1, x0:x1] is the
    part to give mesh3d_block(part, lo, hi, region=(start, shape), ...).  The
    block's cubes [lo, hi) grown by `halo` cubes (the window the block's
    warping decisions are made in: 2 cubes, doubled while a decision in the
    block depends on its edge), the voxel cells around it and the voxels
    their values depend on (several materials: their 3 x 3 x 3
    neighbourhoods; one region: the distance band's reach), one voxel for
    rounding.  Several materials (materials= a label list), or one region
    (label=, with region_facts= from merge_region_facts); no voxel is read."""
    shape = tuple(_integer("shape", n, 2) for n in shape)
    options = _options3(block_voxels, locals(), label, labels, None, None, materials=materials)
    lo = tuple(_integer("lo", v, 0) for v in lo)
    hi = tuple(_integer("hi", v, 1) for v in hi)
    part = np.zeros((1, 1, 1), np.uint8)
    box = _core.block_voxels(_input3(part, voxel_size, origin, options, None, ((0, 0, 0), shape)), lo, hi,
                             _integer("halo", halo, 0), options, region_facts)
    return _zyx(box)


def mesh3d_block(volume, lo, hi, *, spacing=None, label=None, labels=None, iso=None, inside=None, materials=None,
                 shapes=None, background="drop", voxel_size=None, origin=(0.0, 0.0, 0.0), face_rule=None, band=None,
                 region=None, region_facts=None):
    """The tetrahedra of the lattice cubes [lo, hi) (each a triple of cube
    indices, within lattice3d's cubes) of the mesh mesh3d would make, with
    every vertex and tetrahedron named by its global key: a dict of numpy
    arrays (picklable), for merge_blocks, with the block's lattice
    ("lattice": spacing, origin, cubes), range ("lo", "hi"), "face_rule",
    "alphas" and the facts of its input the merged report needs.  Blocks mesh
    independently (a worker needs only its input); blocks that tile the
    lattice merge into exactly mesh3d's mesh and report (with the same
    face_rule; several materials: with their regions, interfaces and region
    names).  Arguments as mesh3d's
    (volumes, shape strings, materials= and shapes=; volume=None with
    shapes=).

    region=(start, shape): `volume` is only a part of a label volume of
    `shape` (nz, ny, nx), starting at voxel `start` (z, y, x) of it (a slice
    of a numpy memmap, a zarr or HDF5 region; origin is the whole's); with
    materials= a label list, or one region (label=) and region_facts= the
    whole region's facts (merge_region_facts), the block reads only this
    part — block_voxels names the part it needs — and the blocks merge into
    exactly the whole volume's mesh and report.  Raises InputError if the
    part lacks a voxel the block read (take block_voxels with a larger
    halo), and for one region without region_facts or with another volume's."""
    options = _options3(mesh3d_block, locals(), label, labels, iso, inside, materials=materials)
    lo = tuple(_integer("lo", v, 0) for v in lo)
    hi = tuple(_integer("hi", v, 1) for v in hi)
    if len(lo) != 3 or len(hi) != 3:
        raise InputError("lo and hi must be triples of cube indices")
    return _core.mesh3d_block(_input3(volume, voxel_size, origin, options, shapes, region), lo, hi, options,
                              region_facts)


def mesh3d_block_read(read, shape, lo, hi, *, halo=2, **options):
    """mesh3d_block of a block that reads only its part of a label volume of
    `shape` (nz, ny, nx): read(start, stop) returns the voxels
    volume[z0:z1, y0:y1, x0:x1] (a numpy memmap's, a zarr array's, an HDF5
    dataset's slice), called with block_voxels' box, and again with twice the
    halo while the block's window needs more.  Options as mesh3d_block's
    (materials= a label list, or label= and region_facts=)."""
    shape = tuple(int(n) for n in shape)
    while True:
        start, stop = block_voxels(shape, lo, hi, halo=halo, **{k: v for k, v in options.items() if k in _BLOCK_VOXELS})
        part = read(start, stop)
        try:
            return mesh3d_block(part, lo, hi, region=(start, shape), **options)
        except InputError as e:
            if "part of the volume is too small" not in str(e) or (start == (0, 0, 0) and stop == shape):
                raise
            halo *= 2


_BLOCK_VOXELS = ("materials", "label", "labels", "band", "spacing", "background", "voxel_size", "origin", "region_facts")


def write_blocks(path, blocks, *, compress=False):
    """Write blocks as a partitioned mesh, never merged in one process: one
    .vtu piece per block (STEM_0000.vtu, ...: its tetrahedra, their
    "region", its vertices; point and cell arrays "GlobalIds" hold the
    vertices' and tetrahedra's global keys, equal wherever pieces share a
    vertex) and the .pvtu at `path` listing them, which ParaView/VTK read as
    one mesh.  The merged mesh (merge_blocks) numbers its vertices in the
    keys' order.  Refused (InputError, nothing written) unless the blocks tile
    one lattice exactly once.  Returns the pieces' file names."""
    path = os.fspath(path)
    if not path.lower().endswith(".pvtu"):
        raise InputError(f"write_blocks writes a .pvtu (and its .vtu pieces), got {path!r}")
    return list(_core.write_blocks_pvtu(path, _block_list(blocks), bool(compress)))


def write_block(block, path, *, compress=False):
    """Write one block as a .vtu piece (as write_blocks does), e.g. on the
    worker that meshed it, and return the piece for write_pvtu: a small
    dict, the block without its arrays (its lattice, range, face rule,
    alphas and facts) with "piece" (the file's path) and its "points" and
    "tetrahedra" counts."""
    path = os.fspath(path)
    _core.write_block_vtu(_block_list([block])[0], path, bool(compress))
    piece = {k: v[:0] if isinstance(v, np.ndarray) else v for k, v in block.items()}
    piece["facts"] = dict(block["facts"], open_face_f=block["facts"]["open_face_f"][:0])
    piece.update(piece=path, points=len(block["vertices"]), tetrahedra=len(block["tets"]))
    return piece


def write_pvtu(path, pieces):
    """The .pvtu at `path` listing .vtu pieces: the pieces write_block
    returns (their blocks must tile one lattice exactly once, from one input
    and options, as merge_blocks checks: InputError naming what is wrong,
    nothing written), or file names relative to the .pvtu's folder (not
    checked)."""
    path, pieces = os.fspath(path), list(pieces)
    if any(isinstance(p, dict) for p in pieces) or not pieces:
        _core.check_blocks(_block_list(pieces))
        folder = os.path.dirname(os.path.abspath(path))
        pieces = [os.path.relpath(os.path.abspath(p["piece"]), folder) for p in pieces]
    _core.write_pvtu(path, [os.fspath(p) for p in pieces])


def _block_list(blocks):
    blocks = list(blocks)
    for i, b in enumerate(blocks):
        if not isinstance(b, dict):
            raise InputError(f"block {i} is a {type(b).__name__}, not a block: give the dicts mesh3d_block returns")
    return blocks


def merge_blocks(blocks):
    """One TetMesh from blocks that tile the lattice (any order): vertices and
    tetrahedra in the global order, the boundary found again; equal to
    mesh3d's mesh of the same input, and its report to mesh3d's (counts,
    face rule, certified bounds, volume, dihedral extremes, radius ratios,
    boundary fidelity, non-manifold counts, materials; but "seconds", and
    "verified": blocks are not verified).

    Every block carries its lattice, cube range ("lo", "hi"), face rule and
    alphas, and what it was made from; raises InputError naming what is
    wrong for an empty list, a missing block (the cubes no block covers),
    blocks that overlap or a block given twice, and blocks of different
    lattices, face rules, alphas, inputs or options."""
    return TetMesh(_core.merge_tet_blocks(_block_list(blocks)))
