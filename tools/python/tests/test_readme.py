# SPDX-License-Identifier: MIT
"""The README's Python example and one-liner, and docs/python.md's joint
example, run, so they cannot go stale."""
import contextlib
import io
import os
import re
import subprocess
import sys

import sfit
from conftest import SOURCE_DIR


def _block(marker, lang, doc="README.md"):
    with open(os.path.join(SOURCE_DIR, doc), encoding="utf-8") as f:
        text = f.read()
    m = re.search(r"<!-- %s:begin -->\n```%s\n(.*?)```\n<!-- %s:end -->" % (marker, lang, marker),
                  text, re.S)
    assert m, "%s block %s not found" % (doc, marker)
    return m.group(1)


def test_readme_example_runs():
    code = _block("python-example", "python")
    out = io.StringIO()
    cwd = os.getcwd()
    os.chdir(SOURCE_DIR)
    try:
        with contextlib.redirect_stdout(out):
            exec(compile(code, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    lines = out.getvalue().splitlines()
    assert lines[0].endswith("gdke sphere 1380 20"), lines[0]
    assert lines[-1] == "too_few_samples"


def test_readme_oneliner_runs():
    cmd = _block("python-oneliner", "sh").strip()
    assert cmd.startswith('/usr/bin/python3 -c "') and cmd.endswith('"')
    code = cmd[len('/usr/bin/python3 -c "'):-1]
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.dirname(os.path.dirname(sfit.__file__))
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                       cwd=SOURCE_DIR, check=True)
    centre = [float(v) for v in p.stdout.strip().strip("[]").split()]
    assert max(abs(a - b) for a, b in zip(centre, (10, 20, 30))) < 1e-3


def test_readme_joint_example_runs():
    if not hasattr(sfit, "Joint"):
        import pytest
        pytest.skip("the C library has no sfit_joint.h yet")
    code = _block("python-joint-example", "python", os.path.join("docs", "python.md"))
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, "docs/python.md", "exec"), {})
    lines = out.getvalue().splitlines()
    centre = [float(v) for v in lines[0].split("]")[0].strip("[ ").split()]
    assert max(abs(a - b) for a, b in zip(centre, (-70, -90, 80))) < 1.0
    assert lines[0].endswith("sphere 500") and lines[1] == "(500, 3)"
