"""The package installs like any Python package: a wheel built from the repository carries the shaders and the
assets, and an installed planetviz renders a preset off-screen from any directory."""
import os
import shutil
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_wheel_installs_and_renders_a_preset_from_elsewhere(tmp_path):
    # 1. Build the wheel as a user would (pip wheel .), from a copy of what it is built from (setuptools
    # writes build/ and *.egg-info/ next to the sources), into a temporary folder.
    source = tmp_path / "source"
    source.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, source / name)
    for name in ("planetviz", "shaders", "assets"):
        shutil.copytree(ROOT / name, source / name, ignore=shutil.ignore_patterns("__pycache__"))
    build = subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", str(source), "-w",
                            str(tmp_path / "dist")], capture_output=True, text=True, timeout=600)
    assert build.returncode == 0, build.stderr[-2000:]
    wheel = next((tmp_path / "dist").glob("planetviz-*.whl"))

    # 2. It holds every Python package under planetviz/, every shader and every asset the code reads.
    names = set(zipfile.ZipFile(wheel).namelist())
    packages = {p.parent.relative_to(ROOT).as_posix() for p in (ROOT / "planetviz").rglob("__init__.py")}
    assert all(f"{p}/__init__.py" in names for p in packages), packages - {n.rsplit("/", 1)[0] for n in names}
    shaders = {f"planetviz/shaders/{p.name}" for p in (ROOT / "shaders").glob("*.glsl")}
    assets = {f"planetviz/assets/{p.relative_to(ROOT / 'assets').as_posix()}"
              for folder in ("atmospheres", "data", "textures") for p in (ROOT / "assets" / folder).iterdir()
              if p.suffix in (".json", ".csv", ".jpg", ".png")}
    assert shaders and assets and not (shaders | assets) - names, (shaders | assets) - names

    # 3. Install it into a fresh virtual environment (its dependencies from this interpreter's site-packages,
    # so that the test needs no download) and run it from a folder that is not the repository.
    env_dir = tmp_path / "venv"
    venv.create(env_dir, system_site_packages=True, with_pip=True)
    python = env_dir / "bin" / "python"
    install = subprocess.run([str(python), "-m", "pip", "install", "-q", "--no-deps", str(wheel)],
                             capture_output=True, text=True, timeout=600)
    assert install.returncode == 0, install.stderr[-2000:]
    work = tmp_path / "elsewhere"
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.update(VTK_DEFAULT_OPENGL_WINDOW="vtkOSOpenGLRenderWindow", PLANETVIZ_CACHE=str(tmp_path / "cache"))
    where = subprocess.run([str(python), "-c", "import planetviz, planetviz.resources as r; "
                            "print(planetviz.__file__); print(r.asset_dir('textures', 'mars.png').is_file())"],
                           cwd=work, env=env, capture_output=True, text=True, timeout=120)
    assert where.returncode == 0, where.stderr[-2000:]
    location, texture = where.stdout.split()
    assert Path(location).is_relative_to(env_dir) and texture == "True", where.stdout
    render = subprocess.run([str(env_dir / "bin" / "planetviz"), "render", "--atmosphere", "mars", "--quality",
                             "draft", "--size", "160x100", "--screenshot", "mars.png", "--exr", "mars.exr"],
                            cwd=work, env=env, capture_output=True, text=True, timeout=600)
    assert render.returncode == 0, render.stderr[-2000:]
    assert (work / "mars.png").stat().st_size > 0 and (work / "mars.exr").stat().st_size > 0
