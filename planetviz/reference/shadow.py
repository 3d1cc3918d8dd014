"""The planet's shadow along straight lines, for the reference solver.

A point p is in the shadow of a planet of radius R lit from the direction s (unit, toward the sun) when
it lies behind the planet, p . s < 0, and inside the cylinder of radius R around the sun's axis,
|p|^2 - (p . s)^2 < R^2. Along a line p(t) = x + t d both conditions are convex in t, so the shadow is one
interval (a, b), possibly empty: the cylinder's quadratic

    f(t) = A t^2 + 2 B t + C,  A = 1 - (d . s)^2,  B = x . d - (x . s)(d . s),  C = |x|^2 - (x . s)^2 - R^2

is negative between its roots, and the half-space condition is t < -(x . s) / (d . s) for d . s > 0 (t >
that for d . s < 0). Distances in metres.
"""
from __future__ import annotations

import numpy as np


def shadow_interval(x, d, s, radius):
    """(a, b) [m], the part of the line x + t d (t real) in the planet's shadow; a >= b where there is none.

    ``x`` (N, 3) [m], ``d`` (N, 3) and ``s`` (N, 3) unit vectors, ``radius`` the planet's [m].
    """
    xs = np.einsum("ij,ij->i", x, s)
    ds = np.einsum("ij,ij->i", d, s)
    xd = np.einsum("ij,ij->i", x, d)
    a_q = np.maximum(1.0 - ds * ds, 0.0)
    b_q = xd - xs * ds
    # |x|^2 - (x.s)^2 is the squared distance from the axis: the perpendicular part, without cancellation.
    perp = x - xs[:, None] * s
    c_q = np.einsum("ij,ij->i", perp, perp) - radius * radius
    disc = b_q * b_q - a_q * c_q
    inf = np.full(len(x), np.inf)
    parallel = a_q < 1e-14
    has_roots = ~parallel & (disc > 0.0)
    sq = np.sqrt(np.where(has_roots, disc, 0.0))
    safe_a = np.where(has_roots, a_q, 1.0)
    lo = np.where(has_roots, (-b_q - sq) / safe_a, np.where(parallel & (c_q < 0.0), -inf, inf))
    hi = np.where(has_roots, (-b_q + sq) / safe_a, np.where(parallel & (c_q < 0.0), inf, -inf))
    # The half-space behind the planet; where ds is subnormal -xs / ds overflows to +-inf, its limit.
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        t0 = np.where(ds != 0.0, -xs / np.where(ds != 0.0, ds, 1.0), 0.0)
    behind_lo = np.where(ds > 0.0, -inf, np.where(ds < 0.0, t0, np.where(xs < 0.0, -inf, inf)))
    behind_hi = np.where(ds > 0.0, t0, np.where(ds < 0.0, inf, np.where(xs < 0.0, inf, -inf)))
    return np.maximum(lo, behind_lo), np.minimum(hi, behind_hi)
