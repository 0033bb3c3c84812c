#!/usr/bin/env python3
"""test_check_layers.py — scripts/check-layers.py fails on planted violations.

Builds a small tree that obeys every rule (the check passes on it), then
plants one violation per rule in a copy of it and requires exit status 1 and
the violation's `file:line: includes X` line; and one entry planted in the
temporary KNOWN list, tolerated while its violation stands and a failure
(stale) once it is gone: the layering check cannot pass silently.
Usage: test_check_layers.py [path/to/check-layers.py]
"""

import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "..", "scripts", "check-layers.py")

# A tree that obeys the rules: path -> lines.
CLEAN = {
    "mesher/include/warpmesh/core/mesh.hpp": ["#pragma once", "#include <vector>"],
    "mesher/include/warpmesh/numerics/interval.hpp": ['#include "warpmesh/core/mesh.hpp"'],
    "mesher/include/warpmesh/mesh2d/generic_square.hpp": ['#include "warpmesh/numerics/interval.hpp"'],
    "mesher/include/warpmesh/mesh3d/generic_bcc.hpp": ['#include "warpmesh/numerics/interval.hpp"'],
    "mesher/include/warpmesh/certify/certified.hpp": ['#include "warpmesh/mesh2d/generic_square.hpp"'],
    "mesher/include/warpmesh/pipeline/mesh2d.hpp": ['#include "warpmesh/certify/certified.hpp"'],
    "mesher/include/warpmesh/warpmesh.hpp": ['#include "warpmesh/pipeline/mesh2d.hpp"'],
    "mesher/src/mesh2d/square_code.hpp": ['#include "warpmesh/core/mesh.hpp"'],
    "mesher/src/mesh2d/uniform/warp.cpp": ['#include "mesh2d/square_code.hpp"', "#include <cmath>"],
    "mesher/src/certify/certified.cpp": ['#include "mesh2d/square_code.hpp"'],
    "mesher/cli/main.cpp": ['#include "warpmesh/warpmesh.hpp"', '#include "warpmesh/prove.hpp"'],
    "prover/include/warpmesh/prove.hpp": ['#include "warpmesh/mesh2d/generic_square.hpp"'],
    "prover/src/bound.cpp": ['#include "warpmesh/prove.hpp"', '#include "warpmesh/numerics/interval.hpp"'],
    "checker/checker.cpp": ["#include <gmp.h>"],
    "python/src/module.cpp": ["#include <warpmesh/warpmesh.hpp>"],
    "tests/support.hpp": ["#pragma once"],
}

# One violation per rule: (file, line appended to it, expected text of the report).
PLANTED = [
    ("mesher/include/warpmesh/core/mesh.hpp", '#include "warpmesh/pipeline/mesh2d.hpp"',
     "mesher/include/warpmesh/core/mesh.hpp:3: includes warpmesh/pipeline/mesh2d.hpp: a layer includes only"),
    ("mesher/include/warpmesh/numerics/interval.hpp", '#include "warpmesh/mesh2d/generic_square.hpp"',
     "(numerics -> mesh2d)"),
    ("mesher/src/mesh2d/uniform/warp.cpp", '#include "warpmesh/mesh3d/generic_bcc.hpp"', "(mesh2d -> mesh3d)"),
    ("mesher/include/warpmesh/certify/certified.hpp", '#include "mesh2d/square_code.hpp"',
     "a public header includes no internal header"),
    ("mesher/include/warpmesh/pipeline/mesh2d.hpp", '#include "warpmesh/warpmesh.hpp"', "umbrella"),
    ("mesher/src/certify/certified.cpp", '#include "warpmesh/prove.hpp"', "the library includes nothing of the prover"),
    ("mesher/cli/main.cpp", '#include "mesh2d/square_code.hpp"', "clients (cli/, tools/, python/src/)"),
    ("prover/src/bound.cpp", '#include "warpmesh/certify/certified.hpp"',
     "prover/src/bound.cpp:3: includes warpmesh/certify/certified.hpp: the provers include"),
    ("prover/src/bound.cpp", '#include "../../tests/support.hpp"', "production tools include no test header"),
    ("checker/checker.cpp", '#include "local.hpp"', "checker/checker.cpp:2: includes local.hpp: the checkers"),
    ("checker/checker.cpp", "#include <warpmesh/core/mesh.hpp>", "the checkers include no project file"),
    ("mesher/src/mesh2d/uniform/warp.cpp", '#include "no_such_file.hpp"', "a quoted include names a project file"),
    ("mesher/src/stray.cpp", "#include <vector>", "mesher/src/stray.cpp:1: lies outside every layer folder"),
    ("mesher/include/warpmesh/flat.hpp", "#include <vector>", "lies outside every layer folder"),
]


def write_tree(root, files):
    for path, lines in files.items():
        full = os.path.join(root, path)
        os.makedirs(os.path.dirname(full), exist_ok=True)
        with open(full, "w") as f:
            f.write("\n".join(lines) + "\n")


def run(root):
    p = subprocess.run([sys.executable, SCRIPT, "--root", root], capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


def main():
    failures, cases = [], 1 + len(PLANTED)
    with tempfile.TemporaryDirectory() as tmp:
        clean = os.path.join(tmp, "clean")
        write_tree(clean, CLEAN)
        status, out = run(clean)
        if status != 0:
            failures.append(f"the clean tree fails (exit {status}):\n{out}")
        for k, (path, line, expected) in enumerate(PLANTED):
            tree = os.path.join(tmp, f"planted{k}")
            shutil.copytree(clean, tree)
            files = {path: CLEAN.get(path, []) + [line]}
            write_tree(tree, files)
            status, out = run(tree)
            if status != 1 or expected not in out:
                failures.append(f"{path} + {line!r}: exit {status}, expected 1 and {expected!r} in:\n{out}")
        # The temporary KNOWN list (empty when no branch is open): an entry
        # tolerates its violation, and an entry whose violation is gone (its
        # file no longer includes the header) fails the check, so the list
        # empties.  One entry planted in the module, checked in process.
        spec = importlib.util.spec_from_file_location("check_layers", SCRIPT)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        src, target, line = PLANTED[3][0], "mesher/src/mesh2d/square_code.hpp", PLANTED[3][1]
        module.KNOWN = {(src, target)}
        cases += 2
        tolerated = os.path.join(tmp, "known")
        shutil.copytree(clean, tolerated)
        write_tree(tolerated, {src: CLEAN[src] + [line]})
        violations, known, _ = module.check(tolerated)
        if violations or known != 1:
            failures.append(f"KNOWN entry {src} -> {target} not tolerated ({known} known):\n" + "\n".join(violations))
        violations, _, _ = module.check(clean)
        if f"{src}:1: includes {target}: stale KNOWN entry" not in "\n".join(violations):
            failures.append(f"stale KNOWN entry {src}: expected the stale line in:\n" + "\n".join(violations))
    for f in failures:
        print("FAIL:", f)
    print(f"{cases - len(failures)}/{cases} cases pass")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
