"""tests/docs/run_examples.py, the runner behind CTest's docs_examples: it
must fail, naming the page and line, when a runnable block fails, and fail
when it finds no runnable block at all (a broken extraction must not pass as
documentation that works)."""
import os
import pathlib
import subprocess
import sys

RUNNER = pathlib.Path(__file__).resolve().parents[1] / "docs" / "run_examples.py"


def build_dir():
    # WARPMESH_EXE is BUILD/mesher/warpmesh (tests/CMakeLists.txt).
    return pathlib.Path(os.environ["WARPMESH_EXE"]).resolve().parents[1]


def run(root):
    return subprocess.run([sys.executable, str(RUNNER), str(root), str(build_dir())],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def page(root, name, text):
    p = root / name
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(text)


def test_passing_blocks_see_the_cli_and_the_module_and_ignore_untagged_ones(tmp_path):
    page(tmp_path, "README.md", "# x\n\n```sh runnable\nwarpmesh --version\n```\n\n```sh\nexit 1\n```\n")
    page(tmp_path, "docs/a.md", "```python runnable\nimport warpmesh\nprint(warpmesh.mesh_shape('circle:0,0,1', spacing=0.2))\n```\n")
    r = run(tmp_path)
    assert r.returncode == 0, r.stdout
    assert "all 2 runnable blocks passed" in r.stdout


def test_a_failing_block_fails_the_run_and_is_named_by_file_and_line(tmp_path):
    page(tmp_path, "README.md", "```sh runnable\ntrue\n```\n")
    page(tmp_path, "docs/b.md", "# b\n\ntext\n\n```sh runnable\nwarpmesh mesh --shape circle:0,0,1 --spacing 0 -o x.vtu\n```\n")
    r = run(tmp_path)
    assert r.returncode == 1
    assert "FAIL  docs/b.md:5" in r.stdout and "1 of 2 runnable blocks failed: docs/b.md:5" in r.stdout


def test_no_runnable_block_at_all_is_a_failure(tmp_path):
    page(tmp_path, "README.md", "```sh\nwarpmesh --version\n```\n")
    r = run(tmp_path)
    assert r.returncode == 1
    assert "no ```sh runnable or ```python runnable block found" in r.stdout
