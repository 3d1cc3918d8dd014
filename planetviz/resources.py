"""The files shipped with planetviz: the GLSL shaders and the assets (preset atmospheres, spectral data,
surface textures).

In the repository they live in the top-level ``shaders/`` and ``assets/`` folders; the wheel carries them
inside the package as ``planetviz.shaders`` and ``planetviz.assets`` (pyproject.toml maps the folders onto
those names), and both are read through :mod:`importlib.resources`, so an installed planetviz finds them
from any working directory.
"""
from __future__ import annotations

import csv
from importlib.resources import files
from pathlib import Path

import numpy as np


def _folder(package: str) -> Path:
    """The file-system folder of a data package (installed from a wheel, or editable)."""
    return Path(str(files(package)))


def shader_dir() -> Path:
    """The folder of the GLSL sources (``shaders/`` in the repository)."""
    return _folder("planetviz.shaders")


def asset_dir(*parts: str) -> Path:
    """A folder or file under the assets (``assets/`` in the repository), e.g. ``asset_dir("textures")``."""
    return _folder("planetviz.assets").joinpath(*parts)


def read_data_csv(name: str) -> dict:
    """The columns of ``assets/data/<name>`` (a CSV file with ``#`` comment lines and a header row) as
    float arrays, by column name."""
    with open(asset_dir("data", name)) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    header, body = rows[0], np.array(rows[1:], dtype=float)
    return {column: body[:, i] for i, column in enumerate(header)}
