"""Planet surface colour maps: equirectangular sRGB images in ``assets/textures`` (see the README there)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

TEXTURES = Path(__file__).resolve().parents[2] / "assets" / "textures"

#: Texture file per planet, by the start of the atmosphere's name.
PLANET_TEXTURES = {"earth": "earth.jpg", "mars": "mars.png"}


def read_image(path):
    """(h, w, 3) uint8 image, top row first; a clear error when the file is missing or unreadable."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkImageReader2Factory
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"surface texture {path} not found")
    reader = vtkImageReader2Factory.CreateImageReader2(str(path))
    if reader is None:
        raise ValueError(f"surface texture {path}: not an image format VTK reads (PNG, JPEG)")
    reader.SetFileName(str(path))
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    data = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)
    if data.shape[-1] < 3 or data.dtype != np.uint8:
        raise ValueError(f"surface texture {path}: an 8-bit RGB image is needed")
    return np.ascontiguousarray(data[::-1, :, :3])


def write_image(path, rgb):
    """Write an (h, w, 3) uint8 image, top row first, as PNG."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOImage import vtkPNGWriter
    h, w, _ = rgb.shape
    image = vtkImageData()
    image.SetDimensions(w, h, 1)
    image.GetPointData().SetScalars(numpy_to_vtk(np.ascontiguousarray(rgb[::-1]).reshape(-1, 3)))
    writer = vtkPNGWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(image)
    writer.Write()


def surface_texture(atm):
    """The colour map of the atmosphere's planet, or None (uniform ground albedo) when there is none."""
    for prefix, name in PLANET_TEXTURES.items():
        if atm.name.startswith(prefix):
            return read_image(TEXTURES / name)
    return None
