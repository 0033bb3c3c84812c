#!/usr/bin/env python3
"""Run every example of the documentation that is marked runnable.

Usage: run_examples.py REPO_ROOT BUILD_DIR [PYTHON]

Reads README.md and docs/*.md under REPO_ROOT and extracts every fenced block
whose opening fence is exactly ```sh runnable or ```python runnable.  Each
block runs in a fresh temporary directory that looks like the repository root
to the example: `mesher/examples`, `tests/data`, `examples`, `proofs` and
`scripts` are symbolic links to the repository's, and `build` is a link to
BUILD_DIR.  So an example is written as a user types it in a clone, after
scripts/build.sh (`warpmesh mesh mesher/examples/brain_axial_s128_labels16.pgm
...`), and the files it writes land in the temporary directory.  The built
`warpmesh` is first on PATH and the built Python module (BUILD_DIR/python) on
PYTHONPATH; WARPMESH_ROOT names the repository root.

sh blocks run under `bash -e -o pipefail`, python blocks under PYTHON
(default /usr/bin/python3, Debian's: it has numpy, meshio, gmsh, dolfinx).
A block that exits non-zero, or runs longer than WARPMESH_DOCS_TIMEOUT
seconds (default 120), fails the test, named by its file and line.  Finding no
runnable block at all is a failure too: it means the extraction broke, not
that the documentation is right.
"""

import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time

FENCE = re.compile(r"^```(\w+)(?:\s+(.*))?$")
LINKED = ("mesher/examples", "tests/data", "examples", "proofs", "scripts")


def blocks(path):
    """Yield (line number of the opening fence, language, text) for each runnable block."""
    lines = path.read_text(encoding="utf-8").splitlines()
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i].rstrip())
        if not m:
            i += 1
            continue
        start, lang, tags = i + 1, m.group(1), (m.group(2) or "").split()
        body = []
        i += 1
        while i < len(lines) and lines[i].rstrip() != "```":
            body.append(lines[i])
            i += 1
        if i == len(lines):
            raise SystemExit(f"{path}:{start}: unterminated fenced block")
        i += 1
        if "runnable" in tags:
            if lang not in ("sh", "python"):
                raise SystemExit(f"{path}:{start}: 'runnable' is for sh and python blocks, not {lang}")
            yield start, lang, "\n".join(body) + "\n"


def sandbox(root, build):
    """A temporary directory that looks like the repository root to an example."""
    d = pathlib.Path(tempfile.mkdtemp(prefix="warpmesh-docs-"))
    for rel in LINKED:
        (d / rel).parent.mkdir(parents=True, exist_ok=True)
        (d / rel).symlink_to(root / rel)
    (d / "build").symlink_to(build)
    return d


def main():
    if len(sys.argv) not in (3, 4):
        raise SystemExit(__doc__)
    root = pathlib.Path(sys.argv[1]).resolve()
    build = pathlib.Path(sys.argv[2]).resolve()
    python = sys.argv[3] if len(sys.argv) == 4 else "/usr/bin/python3"
    timeout = float(os.environ.get("WARPMESH_DOCS_TIMEOUT", "120"))
    exe_dir = build / "mesher"
    if not (exe_dir / "warpmesh").exists():
        raise SystemExit(f"no warpmesh executable in {exe_dir}")

    env = dict(os.environ)
    env["PATH"] = f"{exe_dir}{os.pathsep}{env.get('PATH', '')}"
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(build / "python"), env.get("PYTHONPATH", "")) if p)
    env["WARPMESH_ROOT"] = str(root)
    env.setdefault("OMP_NUM_THREADS", "2")
    env["MPLBACKEND"] = "Agg"

    pages = [root / "README.md"] + sorted((root / "docs").glob("*.md"))
    found, failed = 0, []
    for page in pages:
        rel = page.relative_to(root)
        for line, lang, text in blocks(page):
            found += 1
            d = sandbox(root, build)
            script = d / ("example.sh" if lang == "sh" else "example.py")
            script.write_text(text, encoding="utf-8")
            cmd = ["bash", "-e", "-o", "pipefail", str(script)] if lang == "sh" else [python, str(script)]
            t0 = time.monotonic()
            try:
                r = subprocess.run(cmd, cwd=d, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                   timeout=timeout, text=True)
                status, out = r.returncode, r.stdout
            except subprocess.TimeoutExpired as e:
                status, out = f"timeout after {timeout:g} s", (e.stdout or b"").decode(errors="replace")
            dt = time.monotonic() - t0
            if status == 0:
                print(f"ok    {rel}:{line} ({lang}, {dt:.1f} s)")
            else:
                print(f"FAIL  {rel}:{line} ({lang}, {dt:.1f} s): exit {status}\n--- block ---\n{text}"
                      f"--- output ---\n{out}--- end ---")
                failed.append(f"{rel}:{line}")
            shutil.rmtree(d, ignore_errors=True)
    if found == 0:
        print("docs_examples: no ```sh runnable or ```python runnable block found in README.md or docs/*.md",
              file=sys.stderr)
        return 1
    if failed:
        print(f"docs_examples: {len(failed)} of {found} runnable blocks failed: {', '.join(failed)}",
              file=sys.stderr)
        return 1
    print(f"docs_examples: all {found} runnable blocks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
