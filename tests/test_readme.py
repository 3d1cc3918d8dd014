"""Every command-line example in README.md runs (slow: the README's examples use standard quality and full-size
frames; CI runs this marker)."""
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def readme_commands():
    text = (ROOT / "README.md").read_text()
    commands = []
    for block in re.findall(r"```\n(.*?)```", text, flags=re.S):
        joined = re.sub(r"\\\n\s*", " ", block)
        for line in joined.splitlines():
            line = line.split("  #")[0].strip()
            if line.startswith(("planetviz ", "python app.py", "bash scripts/run.sh")):
                commands.append(line)
    return commands


def test_the_readme_has_the_examples_this_test_runs():
    cmds = readme_commands()
    assert any(c.startswith("python app.py --preset mars") for c in cmds)
    assert any(c.startswith("planetviz render") for c in cmds) and len(cmds) >= 12


@pytest.mark.slow
@pytest.mark.parametrize("command", readme_commands())
def test_readme_example_runs(command, tmp_path):
    env = dict(os.environ, VTK_DEFAULT_OPENGL_WINDOW="vtkOSOpenGLRenderWindow")
    if "Q.npz" in command and not command.startswith("planetviz queries"):
        # The README's own command makes the queries file, as a reader would run it first.
        make = next(c for c in readme_commands() if c.startswith("planetviz queries"))
        proc = subprocess.run([sys.executable, "-m", "planetviz"] + shlex.split(make)[1:], cwd=tmp_path, env=env,
                              capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, (make, proc.stderr[-2000:])
    before = set(ROOT.iterdir())
    args = shlex.split(command)
    if args[0] == "planetviz":
        args = [sys.executable, "-m", "planetviz"] + args[1:]
    elif args[0] == "python":
        args = [sys.executable, str(ROOT / args[1])] + args[2:]
    else:
        args = ["bash", str(ROOT / args[1])] + args[2:]
    proc = subprocess.run(args, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, (command, proc.stderr[-2000:])
    assert set(ROOT.iterdir()) == before, "the example wrote into the repository"
    for token in args:
        if token.endswith((".png", ".exr", ".npz")) and "/" not in token:
            assert (tmp_path / token).stat().st_size > 0, token
