"""Pictures of a scene compared in CIE Y: what the benchmarks and tests of the renderers (per pixel, per vertex,
the quick view) share. A view is (the camera call of :class:`~planetviz.render.Scene`, its keywords, the sun's
keywords); the sun is set from the camera's site."""
from __future__ import annotations

import numpy as np

#: The view classes the pictures are compared in: name: (camera call, keywords, sun keywords).
VIEWS = {
    "orbit, day": ("view_from_space", dict(latitude=20, longitude=10), dict(elevation=30, azimuth=100)),
    "orbit, terminator": ("view_from_space", dict(latitude=0, longitude=0), dict(elevation=0, azimuth=90)),
    "orbit, night side": ("view_from_space", dict(latitude=0, longitude=0), dict(elevation=-60, azimuth=90)),
    "limb from 400 km": ("view_from_ground", dict(latitude=20, altitude=4e5, heading=90, pitch=-17, fov=40),
                         dict(elevation=20, azimuth=90)),
    "aircraft, 10 km": ("view_from_ground", dict(latitude=45, altitude=1e4, heading=90, pitch=0),
                        dict(elevation=20, azimuth=120)),
    "ground, noon": ("view_from_ground", dict(latitude=45, heading=180, pitch=10), dict(elevation=60, azimuth=180)),
    "ground, sunset": ("view_from_ground", dict(latitude=45, heading=270, pitch=2), dict(elevation=2, azimuth=270)),
    "ground, twilight": ("view_from_ground", dict(latitude=45, heading=270, pitch=2), dict(elevation=-4, azimuth=270)),
}


def view_luminance(scene, view):
    """CIE Y [cd/m^2] (h, w) of ``scene``'s picture of ``view``, read back in float (``render_hdr``), the sun's
    disc left out."""
    call, camera, sun = view
    scene.settings.show_sun = False
    getattr(scene, call)(**camera)
    scene.set_sun(**sun, latitude=camera["latitude"], longitude=camera.get("longitude", 0.0))
    return scene.render_hdr().linear_srgb[..., 1]


def floored_difference(y, reference, floor_share=0.01):
    """|y - reference| / max(reference, floor_share x the reference's 99th percentile): relative, a pixel darker
    than the floor counting against the floor (the comparison of the pictures in docs/benchmarks.md)."""
    floor = floor_share * np.percentile(reference, 99)
    return np.abs(y - reference) / np.maximum(reference, floor)

