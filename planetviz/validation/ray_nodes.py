"""The multiple-scattering stage's nodes along rays checked by a conservation law: the light a ray takes out of a
beam, int_0^d beta(t) T(0, t) dt, is 1 - T(0, d) at every wavelength, whatever the atmosphere."""
from __future__ import annotations

import numpy as np

from ..reference.optical_depth import optical_depth
from ..tables.nodes import LONG_RAY_NODE_FACTOR, altitude, integration_grid, split_ray_nodes
from ..tables.precompute import QUALITY, precompute, sizes_for


def extinguished_light_error(atm, thick, quality="standard"):
    """(the relative error (rays, W) of the stage's nodes integrating int_0^d beta(t) T(0, t) dt against its exact
    value 1 - T(0, d), the exact value's own error); the rays of the multiple-scattering tables' integration grid
    at ``quality`` (``precompute.sizes_for``), one per (r, mu) texel.

    Steps: the nodes of ``nodes.split_ray_nodes`` on every ray (three segments, five where ``thick``), n per side
    and ``LONG_RAY_NODE_FACTOR`` n on rays longer than the ground's horizontal ray, as ``multiple._ray_paths``
    takes them; T at the nodes and at d from the reference solver's optical depth (``reference.optical_depth``: 8
    and 16 panels of 16 Gauss-Legendre nodes on each side of the closest approach); the exact value's own error,
    the largest change of 1 - T(0, d) from 16 to 32 panels. Rays whose 1 - T(0, d) is below 1e-3 are NaN.

    Example
    -------
    >>> from planetviz import load_atmosphere
    >>> error, own = extinguished_light_error(load_atmosphere("exo-co2-thick"), thick=True, quality="draft")
    >>> bool(np.nanmax(np.abs(error)) < 0.05 and own < 1e-4)
    True
    """
    sizes = sizes_for(atm, QUALITY[quality])
    tables = precompute(atm, QUALITY["draft"], multiple=False, cache=None)
    r, mu, _, _, _, d = (a[:, :, 0, 0].ravel() for a in integration_grid(tables, sizes.multiple))
    origin = np.stack([np.zeros_like(r), np.zeros_like(r), r], -1)
    direction = np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), mu], -1)

    def depth(i, t, panels):
        """The optical depth (rays, K, W) from the start of the rays ``i`` to the distances t (rays, K)."""
        shape = t.shape + (3,)
        return optical_depth(atm, np.broadcast_to(origin[i][:, None], shape),
                             np.broadcast_to(direction[i][:, None], shape), t, panels=panels)

    error = np.full(d.shape + (atm.n_wavelengths,), np.nan)
    own = 0.0
    long_ray = d > np.sqrt(tables.top ** 2 - tables.bottom ** 2)
    for long in (False, True):
        i = long_ray == long
        n = sizes.multiple_samples * (LONG_RAY_NODE_FACTOR if long else 1)
        t, w = split_ray_nodes(atm, r[i], mu[i], d[i], n, 3.0, thick=thick)
        beta = atm.extinction(altitude(r[i][:, None], mu[i][:, None], t, atm.bottom_radius_m))
        got = np.einsum("rk,rkw->rw", w, beta * np.exp(-depth(i, t, 8)))
        exact, finer = (1.0 - np.exp(-depth(i, d[i][:, None], panels)[:, 0]) for panels in (16, 32))
        bright = exact > 1e-3
        error[i] = np.where(bright, got / np.maximum(exact, 1e-300) - 1.0, np.nan)
        own = max(own, float(np.max(np.abs(finer[bright] / exact[bright] - 1.0), initial=0.0)))
    return error, own
