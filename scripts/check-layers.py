#!/usr/bin/env python3
"""check-layers.py — the include rules of warpmesh, and their check.

This file is the one home of the layering rules (ARCHITECTURE.md, "Layers",
points here; `scripts/check-layers.py --rules` prints them).  It reads every
`#include` of the C++ files under mesher/, prover/, checker/ and python/src/,
resolves it to a file of the tree (the including file's folder first, then
the include roots mesher/include, prover/include, mesher/src) and fails when
one crosses a forbidden boundary:

  file:line: includes X: rule

one line per violation, exit status 1; otherwise one summary line, exit 0.
Run by scripts/test.sh after the build and by CTest (layering,
layering_fails_on_a_planted_violation).

Usage: check-layers.py [--root DIR] [--rules]
"""

import argparse
import os
import re
import sys

# ---- the rules ---------------------------------------------------------------

# The library's layers, low to high.  Each is a folder of public headers,
# mesher/include/warpmesh/<layer>/, and a folder of sources and internal
# headers, mesher/src/<layer>/ (subfolders allowed).  A file of layer L may
# include the public and internal headers of its own layer and of every layer
# of a lower rank; layers of equal rank (mesh2d, mesh3d) are siblings and
# include each other only through EXTRA_ALLOWED.
LAYERS = {
    "core": 0,      # mesh, tetrahedral mesh, buffers, errors, memory admission
    "numerics": 1,  # intervals, rounding, the three-valued comparison (core only)
    "io": 2,        # image and volume readers, mesh writers
    "levelset": 3,  # level sets: shapes, images, volumes
    "mesh2d": 4,    # the 2D stages: lattice, uniform, graded, materials
    "mesh3d": 4,    # the 3D stages: BCC lattice, signs, cut points, warp, tetrahedra
    "certify": 5,   # the proofs' bounds compiled in, keys looked up, verification
    "post": 6,      # quality, mesh checks, optimisation, resolution
    "report": 7,    # reports as text and JSON
    "pipeline": 8,  # one entry point per dimension (mesh2d, mesh3d), slices, options
}

# Includes allowed across the rank order, as (including layer, included file).
EXTRA_ALLOWED: set = set()  # none: the BCC model's Truth and ScalarOps are numerics/scalar.hpp's

# The umbrella header: includes any public header; no library file includes it.
UMBRELLA = "mesher/include/warpmesh/warpmesh.hpp"

# The definitions the provers are about, written once and templated on the
# scalar: with core, numerics and their own headers (prover/), all a prover
# may include.
GENERIC_MODELS = {
    "mesher/include/warpmesh/mesh2d/generic_square.hpp",
    "mesher/include/warpmesh/mesh2d/square_keys.hpp",
    "mesher/include/warpmesh/mesh3d/generic_a15.hpp",
    "mesher/include/warpmesh/mesh3d/generic_a15_keys.hpp",
    "mesher/include/warpmesh/mesh3d/generic_bcc.hpp",
    "mesher/include/warpmesh/mesh3d/generic_bcc_keys.hpp",
    "mesher/include/warpmesh/mesh3d/generic_bcc_materials.hpp",
    "mesher/include/warpmesh/mesh3d/generic_octree.hpp",
}
PROVER_LAYERS = {"core", "numerics"}

# Clients of the library: any public header (mesher/include/, and the
# prover's prover/include/ for `warpmesh prove`), no internal one.  The tests
# (tests/) are clients too and may also include internal headers; they are not
# scanned.
CLIENT_DIRS = ("mesher/cli/", "mesher/tools/", "python/src/")

# The folders scanned; the checkers (checker/) include no project file at all.
SCANNED = ("mesher/", "prover/", "checker/", "python/src/")
SOURCE_EXT = (".hpp", ".cpp", ".h", ".hh", ".cc", ".ipp", ".inl")
INCLUDE_ROOTS = ("mesher/include", "prover/include", "mesher/src")

RULES = {
    "layer": "a layer includes only its own and lower layers (ARCHITECTURE.md, Layers)",
    "sibling": "mesh2d and mesh3d are siblings: neither includes the other",
    "internal": "a public header includes no internal header (mesher/src/)",
    "umbrella": "no library file includes the umbrella warpmesh/warpmesh.hpp",
    "library-prover": "the library includes nothing of the prover (prover/) or the tests (tests/)",
    "client": "clients (cli/, tools/, python/src/) and the umbrella include public headers only",
    "prover": "the provers include core, numerics, the generic models and their own headers only",
    "prover-test": "production tools include no test header (tests/)",
    "checker": "the checkers include no project file (trust boundary: system headers only)",
    "placement": "a library file lies in a layer folder (include/warpmesh/<layer>/ or src/<layer>/)",
    "unresolved": "a quoted include names a project file (system headers take <...>)",
}

# ---- temporary: violations being fixed on other branches ---------------------
# (including file, included file) pairs tolerated until the branch named in the
# comment is merged; the lead removes each entry with that merge.  An entry
# whose violation is gone fails the check ("stale"), so this list empties.
KNOWN: set[tuple[str, str]] = set()

# ---- the check ----------------------------------------------------------------

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def layer_of(path):
    """('public'|'internal', layer) for a library file, 'umbrella', or None."""
    if path == UMBRELLA:
        return "umbrella", None
    for kind, prefix in (("public", "mesher/include/warpmesh/"), ("internal", "mesher/src/")):
        if path.startswith(prefix):
            head = path[len(prefix):].split("/")
            return kind, (head[0] if len(head) > 1 and head[0] in LAYERS else None)
    return None


def resolve(root, including, text, quoted):
    """The included file as a path relative to root, or None (a system header)."""
    candidates = []
    if quoted:
        candidates.append(os.path.join(os.path.dirname(including), text))
    if quoted or text.startswith("warpmesh/"):
        candidates += [os.path.join(r, text) for r in INCLUDE_ROOTS]
    for c in candidates:
        full = os.path.normpath(os.path.join(root, c))
        if os.path.isfile(full):
            return os.path.relpath(full, root).replace(os.sep, "/")
    return None


def library_rule(src_kind, src_layer, target):
    """The rule a library file of src_layer breaks by including target, or None."""
    if target == UMBRELLA:
        return "umbrella"
    t = layer_of(target)
    if t is None:
        return "library-prover"
    t_kind, t_layer = t
    if t_layer is None:
        return "placement"
    if src_kind == "public" and t_kind == "internal":
        return "internal"
    if t_layer == src_layer or (src_layer, target) in EXTRA_ALLOWED:
        return None
    if LAYERS[t_layer] == LAYERS[src_layer]:
        return "sibling"
    return "layer" if LAYERS[t_layer] > LAYERS[src_layer] else None


def layer_detail(src, target):
    """' (a -> b)' for two library files of known layers, else ''."""
    s, t = layer_of(src), layer_of(target or "")
    return f" ({s[1]} -> {t[1]})" if s and t and s[1] and t[1] else ""


def rule_broken(src, target, quoted):
    """The rule that src including target breaks, or None when it is allowed."""
    if src.startswith("checker/"):
        return "checker" if quoted or target else None
    if target is None:
        return "unresolved" if quoted else None
    if src == UMBRELLA:
        t = layer_of(target)
        return None if t and t[0] == "public" and target != UMBRELLA else "client"
    if src.startswith(CLIENT_DIRS):
        own = next(d for d in CLIENT_DIRS if src.startswith(d))
        public = target.startswith(("mesher/include/warpmesh/", "prover/include/", own))
        return None if public else "client"
    if src.startswith("prover/"):
        if target.startswith("prover/") or target in GENERIC_MODELS:
            return None
        if target.startswith("tests/"):
            return "prover-test"
        t = layer_of(target)
        return None if t and t[0] == "public" and t[1] in PROVER_LAYERS else "prover"
    s = layer_of(src)
    if s is None or s[1] is None:
        return "placement"
    return library_rule(s[0], s[1], target)


def scanned_files(root):
    for top in SCANNED:
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            dirs.sort()
            for name in sorted(files):
                if name.endswith(SOURCE_EXT):
                    yield os.path.relpath(os.path.join(folder, name), root).replace(os.sep, "/")


def check(root):
    violations, known_seen, counts = [], set(), {"files": 0, "includes": 0}
    for src in scanned_files(root):
        counts["files"] += 1
        if src != UMBRELLA and src.startswith("mesher/") and not src.startswith(CLIENT_DIRS):
            placed = layer_of(src)
            if placed is None or placed[1] is None:
                violations.append(f"{src}:1: lies outside every layer folder: {RULES['placement']}")
                continue
        with open(os.path.join(root, src), encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                quoted, text = m.group(1) == '"', m.group(2)
                target = resolve(root, src, text, quoted)
                if target is not None:
                    counts["includes"] += 1
                rule = rule_broken(src, target, quoted)
                if rule is None:
                    continue
                if (src, target) in KNOWN:
                    known_seen.add((src, target))
                    continue
                detail = layer_detail(src, target) if rule in ("layer", "sibling") else ""
                violations.append(f"{src}:{number}: includes {text}: {RULES[rule]}{detail}")
    for src, target in sorted(KNOWN - known_seen):
        if os.path.isfile(os.path.join(root, src)):
            violations.append(f"{src}:1: includes {target}: stale KNOWN entry, the violation is gone: "
                              "remove it from scripts/check-layers.py")
    return violations, len(known_seen), counts


def print_rules():
    print("Layers, low to high (a layer includes its own and lower layers; equal ranks are siblings):")
    for name, rank in LAYERS.items():
        print(f"  {rank}  {name:9s} mesher/include/warpmesh/{name}/, mesher/src/{name}/")
    print("Allowed across: " + ", ".join(f"{a} -> {b}" for a, b in sorted(EXTRA_ALLOWED)))
    print(f"Umbrella: {UMBRELLA}")
    print("Provers may include: " + ", ".join(sorted(PROVER_LAYERS)) + ", " + ", ".join(sorted(GENERIC_MODELS)) +
          ", prover/")
    print("Clients: " + ", ".join(CLIENT_DIRS))
    print("Rules:")
    for text in RULES.values():
        print(f"  - {text}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."),
                        help="the tree to check (default: this repository)")
    parser.add_argument("--rules", action="store_true", help="print the rules and exit")
    args = parser.parse_args()
    if args.rules:
        print_rules()
        return 0
    root = os.path.abspath(args.root)
    if not os.path.isdir(os.path.join(root, "mesher")):
        print(f"check-layers: {root} has no mesher/ folder", file=sys.stderr)
        return 2
    violations, known, counts = check(root)
    for v in violations:
        print(v)
    status = "FAILED" if violations else "ok"
    print(f"check-layers: {status}: {counts['files']} files, {counts['includes']} project includes, "
          f"{len(violations)} violations, {known} known (temporary, KNOWN)", file=sys.stderr if violations else sys.stdout)
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main())
