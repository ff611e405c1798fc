"""The worked examples run as scripts from / (not the source tree): their data come through the
package (ramtk.robot_path, the simulators), and each checks its own results against truth."""
import os
import pathlib
import subprocess
import sys

import pytest

EXAMPLES = sorted((pathlib.Path(__file__).resolve().parents[1] / "examples").glob("*.py"))


@pytest.mark.parametrize("example", EXAMPLES, ids=[e.stem for e in EXAMPLES])
def test_example_runs_from_the_root_folder(example, scratch):
    r = subprocess.run([sys.executable, str(example), "--out", str(scratch / f"example_{example.stem}")], cwd="/",
                       capture_output=True, text=True, env=dict(os.environ))
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.rstrip().endswith("ok")
