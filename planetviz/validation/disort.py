"""The plane-parallel limit against DISORT, the discrete-ordinates solver of the atmospheric-science community
(PythonicDISORT on PyPI, the ``test`` extra): an outside, deterministic answer for all orders of scattering on a
planet of the format's largest radius, per ../shared/notes/disort.md's conventions."""
from __future__ import annotations

import warnings

import numpy as np

from ..model.presets import load_atmosphere


def plane_parallel_atmosphere(aerosol: bool, radius_m: float = 1.0e9):
    """A planet of radius ``radius_m`` (at the format's largest, 1e9 m, plane-parallel to 1e-3 over a 60 km
    atmosphere: :func:`curvature_error`), Earth's Rayleigh layer, optionally an absorbing aerosol with a peaked
    phase function (g1 = 0.85, g2 = -0.1, alpha = 0.9), no absorbing layer, ground albedo 0.3.

    >>> plane_parallel_atmosphere(False).bottom_radius_m
    1000000000.0
    """
    earth = load_atmosphere("earth").to_dict()
    d = dict(earth, name="plane-parallel", bottom_radius_m=radius_m, top_radius_m=radius_m + 6.0e4, absorption=[],
             ground_albedo=[0.3, 0.3, 0.3])
    zero = [0.0, 0.0, 0.0]
    d["mie"] = dict(earth["mie"], scattering_m=[1.8e-5, 2.0e-5, 2.2e-5] if aerosol else zero,
                    extinction_m=[2.0e-5, 2.2e-5, 2.45e-5] if aerosol else zero,
                    phase={"g1": [0.85, 0.85, 0.85], "g2": [-0.1, -0.1, -0.1], "alpha": [0.9, 0.9, 0.9]})
    return type(load_atmosphere("earth")).from_dict(d)


#: The plane-parallel twin's largest thickness, as a share of its planet's radius (20 km at 1e9 m). A ray 78 deg
#: from the vertical crosses 4.7 times the air's depth sideways, and the sun's and the view's zenith angles turn by
#: that over the radius along it: random atmosphere 100006 kept at its 13,500 km on a planet of 1e9 m read its
#: single scattering 16.6% off the same integral over a plane-parallel slab (``plane_parallel_single_scattering``)
#: on ground_and_top_views' rays, 1.2% at 1000 km and 0.12% at 100 km. tests/test_tables_disort.py holds random
#: atmospheres' twins within 0.1% of the slab, a third of DISORT's own 0.3%.
PLANE_PARALLEL_THICKNESS = 2.0e-5


def plane_parallel_twin(atm, radius_m: float = 1.0e9):
    """``atm`` in its plane-parallel limit: on a planet of ``radius_m`` (by default the format's largest), its
    absorbing layers left out (DISORT's layers here hold the molecules and the particles), and no thicker than
    ``PLANE_PARALLEL_THICKNESS`` times the radius. A thicker atmosphere has every length of its profiles and its
    thickness divided by one factor k and its coefficients multiplied by k: the optical depth between any two
    fractions of its thickness is kept, and with it everything a plane-parallel sky depends on.

    >>> from planetviz.validation import random_atmosphere
    >>> twin = plane_parallel_twin(random_atmosphere(4))
    >>> twin.absorption, round(twin.thickness_m)
    ((), 20000)
    """
    k = max(atm.thickness_m / (PLANE_PARALLEL_THICKNESS * radius_m), 1.0)
    d = atm.to_dict()
    d.update(bottom_radius_m=radius_m, top_radius_m=radius_m + atm.thickness_m / k, absorption=[])
    d["rayleigh"] = dict(d["rayleigh"], scattering_m=[b * k for b in d["rayleigh"]["scattering_m"]],
                         profile=_shrunk(d["rayleigh"]["profile"], k))
    d["mie"] = dict(d["mie"], scattering_m=[b * k for b in d["mie"]["scattering_m"]],
                    extinction_m=[b * k for b in d["mie"]["extinction_m"]], profile=_shrunk(d["mie"]["profile"], k))
    return type(atm).from_dict(d)


def only_wavelengths(atm, keep):
    """The atmosphere ``atm`` with only its wavelengths of index in ``keep`` (a sequence of ints): one channel's
    sky, solved on its own, as with the others (the wavelengths scatter independently)."""
    d = atm.to_dict()
    pick = lambda values: [values[w] for w in keep]
    d.update(wavelengths_nm=pick(d["wavelengths_nm"]), ground_albedo=pick(d["ground_albedo"]))
    d["rayleigh"] = dict(d["rayleigh"], scattering_m=pick(d["rayleigh"]["scattering_m"]))
    d["mie"] = dict(d["mie"], scattering_m=pick(d["mie"]["scattering_m"]), extinction_m=pick(d["mie"]["extinction_m"]),
                    phase={k: pick(v) for k, v in d["mie"]["phase"].items()})
    return type(atm).from_dict(d)


def _shrunk(profile: dict, k: float) -> dict:
    """A profile's dictionary with its lengths (the fields named ``*_m``) divided by k."""
    return {key: (np.divide(value, k).tolist() if key.endswith("_m") else value) for key, value in profile.items()}


def isotropic_atmosphere(optical_depth, omega, albedo=0.3, scale_height_m=8000.0):
    """A plane-parallel planet (:func:`plane_parallel_atmosphere`) whose only scatterers are isotropic particles of
    total optical depths ``optical_depth`` (one per wavelength) and single-scattering albedo ``omega``, on a
    Lambertian ground of ``albedo``: where an isotropic model of the orders of scattering is exact.

    >>> isotropic_atmosphere((0.1, 1.0, 2.0), 0.95).mie.g1
    (0.0, 0.0, 0.0)
    """
    d = plane_parallel_atmosphere(False).to_dict()
    zero = [0.0, 0.0, 0.0]
    extinction = [tau / scale_height_m for tau in optical_depth]
    d["rayleigh"] = dict(d["rayleigh"], scattering_m=zero)
    d["mie"] = dict(d["mie"], scattering_m=[e * omega for e in extinction], extinction_m=extinction,
                    profile={"type": "exponential", "scale_height_m": scale_height_m},
                    phase={"g1": zero, "g2": zero, "alpha": [1.0, 1.0, 1.0]})
    d["ground_albedo"] = [albedo] * 3
    return type(load_atmosphere("earth")).from_dict(d)


def disort_radiance(atm, w, mu0, views, n_quad=64, layers=120):
    """Radiance [1/sr per unit irradiance normal to the beam] at wavelength index w from PythonicDISORT, the sun's
    cosine ``mu0``, for the views (mu, phi, t): mu < 0 looking up, phi the view's azimuth from the sun's, t the
    optical depth's fraction from the top (0 the top, 1 the ground). Plane-parallel, exponential profiles only;
    layers thin at the ground (2 m, 2 km at the top; exact layer-mean coefficients), delta-M with the
    Nakajima-Tanaka correction where the particles scatter, the Lambertian ground as its zeroth BDRF mode; the
    direct beam excluded. 64 streams against 128 differ by at most 0.3% (median 2e-5, ../shared/notes/disort.md)
    where the particles' lobes have g up to 0.88, but not under a sharper lobe that holds most of their scattering:
    the ground_and_top_views of random atmosphere 195's 440 nm channel (g1 = 0.92, weight 0.93) by 6.9% at most
    (1.2% RMS), 473's at 550 nm (g2 = 0.95) 5.8%, 100022's at 680 nm (g2 = 0.92) 9.4%, each at the view 10 deg from
    the sun; there 128 streams are within 0.05% of 160 and 192 (``n_quad``; docs/benchmarks.md).
    """
    from PythonicDISORT.subroutines import interpolate
    u, _, tau_cum, peaked = _solve(atm, w, mu0, n_quad, layers)
    u = interpolate(u, NT_cor="eval" if peaked else None)
    return np.array([u(mu, t * tau_cum[-1], phi).item() for mu, phi, t in views])


def plane_parallel_single_scattering(atm, w, mu0, views, panels=400):
    """Single scattering plus directly lit ground [1/sr per unit irradiance normal to the beam] at wavelength index
    w over a plane-parallel slab of ``atm``'s exponential profiles, the sun's cosine ``mu0``, for the views (mu, phi,
    t) of :func:`disort_radiance` with t = 1 (the ground, mu < 0) or t = 0 (the top, mu > 0):

    L_1 = int_0^Z beta^scat(z) P(nu) exp(-tau(z) / mu0) exp(-tau_v(z) / |mu|) dz / |mu|
          + [t = 0] exp(-tau* / mu) (a / pi) mu0 exp(-tau* / mu0),

    tau(z) the optical depth from z to the top (exact for exponential profiles), tau_v(z) the view's, tau(z) at the
    top and tau* - tau(z) at the ground, nu = sqrt(1 - mu^2) cos(phi) sin(theta0) - mu mu0 the cosine between the
    view direction (against the light's) and the sun's. Gauss-Legendre, 8 nodes on each of ``panels`` layers whose
    thickness grows geometrically from the ground, as :func:`disort_radiance`'s do. What the sphere of the same
    atmosphere's single scattering (reference/single.py) differs from it by is the planet's curvature.
    """
    mu, phi, t = (np.array(x, dtype=float) for x in zip(*views))
    if not np.all(((t == 1.0) & (mu < 0.0)) | ((t == 0.0) & (mu > 0.0))):
        raise ValueError("plane_parallel_single_scattering: views must be at the ground looking up (t = 1, mu < 0) "
                         "or at the top looking down (t = 0, mu > 0)")
    edges = _layer_edges(atm, panels)
    nodes, weights = np.polynomial.legendre.leggauss(8)
    half = 0.5 * np.diff(edges)[:, None]
    z = (0.5 * (edges[1:] + edges[:-1])[:, None] + half * nodes).ravel()
    dz = (half * weights).ravel()
    tau = _optical_depth_from_top(atm, w, z)
    tau_star = _optical_depth_from_top(atm, w, np.zeros(1))[0]
    beta_r = atm.rayleigh.scattering_m[w] * np.exp(-z / atm.rayleigh.profile.scale_height_m)
    beta_m = atm.mie.scattering_m[w] * np.exp(-z / atm.mie.profile.scale_height_m)
    sin0 = np.sqrt(1.0 - mu0 * mu0)
    nu = np.sqrt(1.0 - mu * mu) * np.cos(phi) * sin0 - mu * mu0
    phase_r = atm.rayleigh.phase_function(nu)[:, None]
    phase_m = atm.mie.phase_function(nu)[:, w][:, None]
    tau_view = np.where((t == 0.0)[:, None], tau, tau_star - tau)
    m = np.abs(mu)[:, None]
    integrand = (beta_r * phase_r + beta_m * phase_m) * np.exp(-tau / mu0 - tau_view / m) / m
    ground = np.where(t == 0.0, np.exp(-tau_star / np.abs(mu)) * atm.ground_albedo[w] / np.pi * mu0
                      * np.exp(-tau_star / mu0), 0.0)
    return integrand @ dz + ground


def curvature_error(atm, sun_zeniths_deg=(30.0, 70.0)):
    """The relative difference (suns, W, views) between ``atm``'s single scattering on its sphere
    (reference/single.py) and over a plane-parallel slab (:func:`plane_parallel_single_scattering`), on the rays of
    :func:`ground_and_top_views` (ground and top alternating), the sun ``sun_zeniths_deg`` from the zenith: how far
    the planet's curvature moves its sky from DISORT's, which holds for a slab, in the first order. Earth's 60 km
    Rayleigh layer reads 0.84% at most on a planet of 1e8 m, 0.08% on one of 1e9 m.
    """
    from .single_scattering import reference_single_scattering
    views, cams, dirs = ground_and_top_views(atm)
    errors = []
    for zenith in np.radians(np.asarray(sun_zeniths_deg, dtype=float)):
        sun = np.array([np.sin(zenith), 0.0, np.cos(zenith)])
        sphere = reference_single_scattering(atm, cams, dirs, np.tile(sun, (len(cams), 1)))
        errors.append([sphere[:, w] / plane_parallel_single_scattering(atm, w, sun[2], views) - 1.0
                       for w in range(atm.n_wavelengths)])
    return np.array(errors)


def disort_mean_radiance(atm, w, mu0, heights_m, n_quad=64, layers=120):
    """The mean over all directions of the diffuse radiance, (1 / 2) int u0 dmu [1/sr per unit irradiance normal to
    the beam], at wavelength index w from PythonicDISORT at the altitudes ``heights_m``, with its own quadrature
    (Gauss-Legendre cosines on each hemisphere) over its zeroth Fourier mode u0; the same atmosphere and layers as
    :func:`disort_radiance`, for particles without a truncated lobe (no delta-M: u0 is then the radiance's
    azimuthal mean)."""
    _, u0, tau_cum, peaked = _solve(atm, w, mu0, n_quad, layers)
    if peaked:
        raise ValueError("disort_mean_radiance: particles with a forward lobe would need delta-M's reclassification")
    tau = _optical_depth_from_top(atm, w, np.asarray(heights_m, dtype=float))
    x, weights = np.polynomial.legendre.leggauss(n_quad // 2)
    return 0.25 * np.sum(np.concatenate([weights, weights])[:, None] * u0(tau), axis=0)


def _layer_edges(atm, layers):
    """The altitudes [m] of the edges of ``layers`` layers from the ground to the top, each thicker than the one
    below by a constant factor (2 m at the ground and 2 km at the top for a 60 km atmosphere and 120 layers)."""
    return atm.thickness_m * np.expm1(6.0 * np.linspace(0.0, 1.0, layers + 1)) / np.expm1(6.0)


def _column(ext, profile, low, high):
    """The optical depth of an exponential component between altitudes low and high [m]."""
    h = profile.scale_height_m
    return ext * h * (np.exp(-low / h) - np.exp(-high / h))


def _optical_depth_from_top(atm, w, heights):
    """Extinction optical depth from the top of the atmosphere down to ``heights`` at wavelength index w."""
    top = atm.thickness_m
    return (_column(atm.rayleigh.scattering_m[w], atm.rayleigh.profile, heights, top)
            + _column(atm.mie.extinction_m[w], atm.mie.profile, heights, top))


def _solve(atm, w, mu0, n_quad, layers):
    """PythonicDISORT's (u, u0, cumulative optical depth of the layers, whether delta-M and NT were used) for the
    layers of :func:`disort_radiance`."""
    from PythonicDISORT import pydisort
    edges = _layer_edges(atm, layers)
    top, bottom = edges[::-1][:-1], edges[::-1][1:]                       # layers from the top down
    tau_r = _column(atm.rayleigh.scattering_m[w], atm.rayleigh.profile, bottom, top)
    tau_ms = _column(atm.mie.scattering_m[w], atm.mie.profile, bottom, top)
    tau_me = _column(atm.mie.extinction_m[w], atm.mie.profile, bottom, top)
    tau = tau_r + tau_me
    omega = np.minimum((tau_r + tau_ms) / tau, 1.0 - 1e-8)
    n_leg = n_quad + 1
    ell = np.arange(n_leg)
    rayleigh = np.zeros(n_leg)
    rayleigh[0], rayleigh[2] = 1.0, 0.1
    g1, g2, alpha = atm.mie.g1[w], atm.mie.g2[w], atm.mie.alpha[w]
    mie = alpha * g1 ** ell + (1.0 - alpha) * g2 ** ell
    leg = (tau_r[:, None] * rayleigh + tau_ms[:, None] * mie) / np.maximum(tau_r + tau_ms, 1e-300)[:, None]
    tau_cum = np.cumsum(tau)
    peaked = atm.mie.scattering_m[w] > 0.0 and (g1 != 0.0 or g2 != 0.0)   # delta-M and NT only for a lobe
    with warnings.catch_warnings():
        # omega = 1 - 1e-8 in the pure Rayleigh layers is the note's recipe for a conservative scatterer.
        warnings.filterwarnings("ignore", message="Some delta-scaled single-scattering albedos")
        _, _, _, u0, u = pydisort(tau_cum, omega, n_quad, leg, mu0, 1.0, 0.0, NLeg=n_quad,
                                  f_arr=leg[:, n_quad] if peaked else 0.0, NT_cor=peaked,
                                  BDRF_Fourier_modes=[float(atm.ground_albedo[w])])
    return u, u0, tau_cum, peaked


def ground_and_top_views(atm, zeniths_deg=(20.0, 55.0, 78.0), azimuths_deg=(0.0, 90.0, 180.0)):
    """(DISORT views (mu, phi, t), cameras (N, 3) [m], view directions (N, 3)) at the ground looking up and at the
    top looking down, at every view zenith angle x azimuth from the sun's (the sun in the x-z plane, x > 0)."""
    rg, rt = atm.bottom_radius_m, atm.top_radius_m
    views, cams, dirs = [], [], []
    for zen in zeniths_deg:
        for az in azimuths_deg:
            z, a = np.radians(zen), np.radians(az)
            horizontal = np.array([np.sin(z) * np.cos(a), np.sin(z) * np.sin(a), 0.0])
            views.append((-np.cos(z), a, 1.0))                               # at the ground, looking up
            cams.append([0.0, 0.0, rg + 1e-3])
            dirs.append(horizontal + [0.0, 0.0, np.cos(z)])
            views.append((np.cos(z), a, 0.0))                                # at the top, looking down
            cams.append([0.0, 0.0, rt + 1.0])
            dirs.append(horizontal - [0.0, 0.0, np.cos(z)])
    return views, np.array(cams), np.array(dirs)
