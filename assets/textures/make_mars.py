"""Generates mars.png: a procedural Mars albedo map (equirectangular, 1024 x 512, sRGB).

No Mars map is available offline from a package registry, so this one is made, not measured: bright ochre
plains and dark basaltic regions from a smooth random field on the sphere (sums of plane waves in 3D, so the
map has no seam at the date line and no pinch at the poles), and white polar caps. Colours are typical
Mars albedos: bright regions ~0.30 and dark ones ~0.15 in red (linear). Deterministic (seed 2020).

    python assets/textures/make_mars.py
"""
from pathlib import Path

import numpy as np


def mars_map(width=1024, height=512, seed=2020):
    rng = np.random.default_rng(seed)
    lat = (0.5 - (np.arange(height) + 0.5) / height) * np.pi          # top row: north
    lon = ((np.arange(width) + 0.5) / width - 0.5) * 2 * np.pi
    lon, lat = np.meshgrid(lon, lat)
    p = np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], -1)
    field = np.zeros(lat.shape)
    for octave, (freq, amp) in enumerate(((1.5, 1.0), (3.0, 0.5), (6.0, 0.25), (12.0, 0.12), (24.0, 0.06))):
        for _ in range(12):
            k = rng.normal(size=3)
            k *= freq / np.linalg.norm(k)
            field += amp * np.sin(p @ k + rng.uniform(0, 2 * np.pi))
    field = (field - field.mean()) / field.std()
    dark = 1.0 / (1.0 + np.exp(-2.5 * (field - 0.6)))                  # dark regions cover ~30%
    bright_lin = np.array([0.30, 0.14, 0.06])                          # linear reflectance R, G, B
    dark_lin = np.array([0.15, 0.08, 0.045])
    albedo = bright_lin * (1 - dark[..., None]) + dark_lin * dark[..., None]
    cap = np.clip((np.abs(np.degrees(lat)) - np.where(lat > 0, 80.0, 83.0)) / 2.0, 0.0, 1.0)
    albedo = albedo * (1 - cap[..., None]) + np.array([0.75, 0.72, 0.68]) * cap[..., None]
    encoded = np.where(albedo <= 0.0031308, 12.92 * albedo, 1.055 * albedo ** (1 / 2.4) - 0.055)
    return np.round(np.clip(encoded, 0, 1) * 255).astype(np.uint8)


def main():
    from planetviz.render.surface import write_image
    write_image(Path(__file__).with_name("mars.png"), mars_map())


if __name__ == "__main__":
    main()
