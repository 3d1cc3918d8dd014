"""The VTK renderer (OSMesa off-screen): the shader against the NumPy evaluator, and what a person would see."""
import os
import subprocess
import sys

import numpy as np
import pytest

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")

from planetviz.render import Scene  # noqa: E402

SIZE = (64, 48)


@pytest.fixture(scope="module")
def earth():
    scene = Scene("earth", quality="draft", surface=None, off_screen=True, window_size=SIZE)
    yield scene
    scene.close()


@pytest.fixture(scope="module")
def mars():
    scene = Scene("mars", quality="draft", surface=None, off_screen=True, window_size=SIZE)
    yield scene
    scene.close()


def tables_radiance(scene, preset, rows, cols, tmp_path):
    """``planetviz radiance --method tables`` for the rays of the given pixels (same quality, same cached tables)."""
    dirs = scene.pixel_directions(rows, cols).reshape(-1, 3)
    q, out = tmp_path / "q.npz", tmp_path / "out.npz"
    np.savez(q, camera_m=np.tile(scene.camera_location, (len(dirs), 1)), view_dir=dirs,
             sun_dir=scene.sun_direction)
    proc = subprocess.run([sys.executable, "-m", "planetviz", "radiance", "--atmosphere", preset,
                           "--queries", q, "--out", out, "--method", "tables", "--quality", "draft"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    with np.load(out) as f:
        return f["radiance"]


def shader_matches_lut(scene, preset, tmp_path):
    """The largest relative difference between the rendered HDR radiance and the tables command's on a grid of
    pixels away from the sun, after checking that both see the planet in the same pixels."""
    hdr = scene.render_hdr()
    rows, cols = np.meshgrid(np.arange(1, SIZE[1], 4), np.arange(1, SIZE[0], 5), indexing="ij")
    keep = away_from_sun(scene, rows, cols)
    want = tables_radiance(scene, preset, rows, cols, tmp_path).reshape(rows.shape + (3,))
    got = hdr.radiance[rows, cols]
    seen = want.max(-1) > 0
    assert keep.sum() > 100 and (seen & keep).sum() > 50
    assert np.array_equal(got.max(-1) > 0, seen)                  # the same pixels see the planet
    return (np.abs(got - want)[keep & seen] / want[keep & seen]).max()


def away_from_sun(scene, rows, cols, degrees=1.0):
    """Pixels whose rays are more than ``degrees`` from the sun (the evaluator has no sun disc)."""
    return scene.pixel_directions(rows, cols) @ scene.sun_direction < np.cos(np.radians(degrees))


@pytest.mark.parametrize("view", ["space", "ground", "aircraft", "twilight", "horizon"])
def test_shader_radiance_matches_the_tables_command(earth, view, tmp_path):
    # The shader and `planetviz radiance --method tables` evaluate the same formulas on the same float32 tables;
    # they differ by the shader's float32 arithmetic (ray set-up, the near-horizon mu mapping, S(x) - T S(y))
    # and, on GPUs, by texture filtering with 8-bit interpolation weights (an error of at most 1/512 of the
    # difference between neighbouring texels, well under 1% for tables that change less than a factor 2 per
    # texel). Bound: 1%, well above both; measured on llvmpipe: at most 2.3e-4 (space).
    if view == "space":
        earth.view_from_space(distance=1.6e7, latitude=10, longitude=20, fov=40)
        earth.set_sun(elevation=40, azimuth=120, latitude=10, longitude=20)
    elif view == "ground":
        earth.view_from_ground(latitude=30, altitude=2.0, heading=80, pitch=5, fov=70)
        earth.set_sun(elevation=20, azimuth=100, latitude=30, longitude=0)
    elif view == "aircraft":
        earth.view_from_ground(latitude=30, altitude=1e4, heading=200, pitch=-10, fov=70)
        earth.set_sun(elevation=8, azimuth=150, latitude=30, longitude=0)
    elif view == "horizon":
        # From 30 km, 8 deg about the horizon's direction (5.56 deg down), a sun 3 deg down behind the camera:
        # every pixel within tables/horizon.py's bands, whose quadrature replaces the tables' reading there (and
        # its GLSL twin, horizon_single_scattering). Measured on llvmpipe: 1.7e-5; with the GLSL twin's blend left
        # out (the tables read as they are) 20%.
        earth.view_from_ground(latitude=30, altitude=3e4, heading=270, pitch=-5.5, fov=8)
        earth.set_sun(elevation=-3.0, azimuth=90, latitude=30, longitude=0)
    else:
        # From 3 km, below the draft tables' row 5, away from a sun 1.5 deg down: the ground rays run into the
        # planet's shadow, and both integrate only their lit part (near_ground.shadow_interval and its GLSL twin).
        # Measured on llvmpipe: 1.0e-5 (space 2.3e-4, ground 2.4e-5, aircraft 9.1e-6); with the GLSL twin's shadow
        # left out (the rays' halves integrated whole) 3.2%.
        earth.view_from_ground(latitude=30, altitude=3e3, heading=270, pitch=-3, fov=70)
        earth.set_sun(elevation=-1.5, azimuth=90, latitude=30, longitude=0)
    assert shader_matches_lut(earth, "earth", tmp_path) < 0.01


def luminance_image(scene):
    return scene.render_hdr().linear_srgb


def test_earth_noon_zenith_is_bluer_than_the_horizon(earth):
    earth.view_from_ground(latitude=0, heading=0, pitch=45, fov=95)
    earth.set_sun(elevation=70, azimuth=180, latitude=0, longitude=0)
    rgb = luminance_image(earth)
    h, w = rgb.shape[:2]
    zenith = rgb[1, w // 2]
    rows = np.nonzero(rgb[:, w // 2].sum(-1) > 0)[0]
    d = earth.pixel_directions(np.arange(h), np.full(h, w // 2))
    horizon_row = np.argmin(np.abs(d @ (earth.camera_location / np.linalg.norm(earth.camera_location)) - 0.02))
    horizon = rgb[horizon_row, w // 2]
    assert len(rows) == h
    assert zenith[2] / zenith[0] > 1.3 * horizon[2] / horizon[0], (zenith, horizon)


def sun_colour(scene, elevation):
    scene.set_sun(elevation=elevation, azimuth=90, latitude=0, longitude=0)
    sun = scene.sun_direction
    scene.set_view(scene.camera_location, sun, fov=2.0)        # the disc fills the middle pixels
    rgb = luminance_image(scene)
    h, w = rgb.shape[:2]
    return rgb[h // 2, w // 2]


def test_the_sun_is_redder_at_sunset_than_at_noon(earth):
    earth.view_from_ground(latitude=0, heading=90, pitch=0)
    noon, sunset = sun_colour(earth, 60.0), sun_colour(earth, 1.0)
    assert noon.min() > 0 and sunset.min() > 0
    # Sunset through ~30 air masses: blue falls far more than red (measured B/R 0.16 vs 0.95).
    assert sunset[2] / sunset[0] < 0.5 * noon[2] / noon[0], (noon, sunset)


def test_space_is_black_away_from_the_planet_and_the_night_side_is_dark(earth):
    earth.view_from_space(distance=4e7, latitude=0, longitude=0, fov=40)
    earth.set_sun(elevation=-90, azimuth=0, latitude=0, longitude=0)  # the sun behind the planet
    night = earth.render_hdr().radiance
    earth.set_sun(elevation=90, azimuth=0, latitude=0, longitude=0)
    day = earth.render_hdr().radiance
    h, w = day.shape[:2]
    d = earth.pixel_directions(*np.meshgrid(np.arange(h), np.arange(w), indexing="ij"))
    cam = earth.camera_location
    closest = np.linalg.norm(cam - (d @ cam)[..., None] * d, axis=-1)
    off = closest > earth.atmosphere.top_radius_m * 1.001
    disc = closest < 0.7 * earth.atmosphere.bottom_radius_m
    assert off.sum() > 100 and disc.sum() > 50
    assert np.all(day[off] == 0) and np.all(night[off] == 0)
    # Night side: no direct sun, no first-order sky; what is left is light scattered around the limb many
    # times, orders of magnitude below the day side (measured ~0 at the disc centre).
    assert night[disc].max() < 1e-4 * day[disc].mean()


def test_mars_sky_is_red_brown_at_noon_and_blue_around_the_setting_sun(mars):
    mars.view_from_ground(latitude=0, heading=0, pitch=30, fov=60)
    mars.set_sun(elevation=70, azimuth=180, latitude=0, longitude=0)
    noon = luminance_image(mars)
    h, w = noon.shape[:2]
    sky = noon[h // 4, w // 2]
    assert sky[0] > sky[1] > sky[2], sky                            # red-brown: R > G > B
    mars.set_sun(elevation=3, azimuth=90, latitude=0, longitude=0)
    mars.view_from_ground(latitude=0, heading=90, pitch=8, fov=60)
    dusk = luminance_image(mars)
    d = mars.pixel_directions(*np.meshgrid(np.arange(h), np.arange(w), indexing="ij"))
    angle = np.degrees(np.arccos(np.clip(d @ mars.sun_direction, -1, 1)))
    up = d @ (mars.camera_location / np.linalg.norm(mars.camera_location)) > 0.02
    near = up & (angle > 2) & (angle < 8)
    far = up & (angle > 25)
    assert near.sum() > 5 and far.sum() > 50
    ratio = lambda m: np.mean(dusk[m][:, 2] / dusk[m][:, 0])
    assert ratio(near) > 1.2 * ratio(far), (ratio(near), ratio(far))   # the blue glow around the sun


def test_hdr_output_is_linear_float_and_written_to_openexr(earth, tmp_path):
    import OpenEXR
    from planetviz.model.color import linear_srgb_matrix
    earth.view_from_ground(latitude=0, heading=90, pitch=0, fov=10)
    earth.set_sun(elevation=2, azimuth=90, latitude=0, longitude=0)  # the sun disc in view: radiance >> 1
    hdr = earth.render_hdr(tmp_path / "view.exr")
    assert hdr.radiance.dtype == np.float32 and hdr.radiance.max() > 1e3
    assert np.allclose(hdr.linear_srgb, hdr.radiance @ linear_srgb_matrix(earth.atmosphere), rtol=1e-4, atol=1e-3)
    with OpenEXR.File(str(tmp_path / "view.exr"), separate_channels=True) as f:
        ch = f.channels()
        assert np.array_equal(ch["G"].pixels, hdr.linear_srgb[..., 1])
        assert np.array_equal(ch["L.550nm"].pixels, hdr.spectral_radiance[..., 1])
        assert "earth" in f.header()["planetviz"]


def test_tables_are_uploaded_as_32_bit_float_textures(earth):
    # 16-bit float tables flicker and band (2^-11 steps); every table texture must stay float32.
    from vtkmodules.vtkCommonCore import VTK_FLOAT
    earth.render()
    textures = earth.planet.textures._textures
    assert textures is not None
    for name, tex in textures.items():
        if name != "surface_faces":
            assert tex.GetVTKDataType() == VTK_FLOAT and tex.GetComponents() == 4, name


@pytest.mark.parametrize("quality", ["draft", "standard", "high"])
def test_no_4d_table_texture_is_a_power_of_two_wide(quality):
    # llvmpipe compiles a shader variant per power-of-two-ness of the textures it samples: with one width for
    # every level the draft tables a window shows before the standard ones draw with the standard tables' program
    # (docs/rendering.md, "Progressive switching"). The draft level's 4 x 16 slices are padded by one column; the
    # twin tests above (draft tables) fail if the shader reads the padded texture with the unpadded width.
    from planetviz.render.textures import pack_3d
    from planetviz.tables import QUALITY
    sizes = QUALITY[quality]
    for n_nu, n_mu_s, n_mu, n_r in (sizes.scattering, sizes.multiple):
        table = np.random.default_rng(0).random((n_r, n_mu, n_nu, n_mu_s, 3), dtype=np.float32)
        volume = pack_3d(table, odd_width=True)
        width = volume.shape[2]
        assert width & (width - 1) != 0 and width in (n_nu * n_mu_s, n_nu * n_mu_s + 1)
        np.testing.assert_array_equal(volume[:, :, :n_nu * n_mu_s], pack_3d(table))


def test_no_jitter_two_metres_above_the_ground_and_no_jump_at_the_top(earth):
    top = earth.atmosphere.top_radius_m
    earth.set_sun(elevation=25, azimuth=90, latitude=0, longitude=0)
    # 2 m above the ground, looking along the horizon: moving 1 cm must not change the picture (float32
    # positions at 6.4e6 m are 0.5 m apart: a renderer working in absolute coordinates jitters here).
    earth.view_from_ground(latitude=0, altitude=2.0, heading=60, pitch=0, fov=20)
    a = earth.render_hdr().radiance
    earth.view_from_ground(latitude=1e-7, altitude=2.01, heading=60, pitch=0, fov=20)
    b = earth.render_hdr().radiance
    assert np.max(np.abs(a - b) / np.maximum(a, 1e-6)) < 2e-3
    # Crossing the top of the atmosphere: 1 m inside and 1 m outside must agree to 0.1% (docs/stability.md).
    up = np.array([1.0, 0.0, 0.0])
    view = np.array([-0.6, 0.8, 0.0])
    pics = []
    for r in (top - 1.0, top + 1.0):
        earth.set_view(up * r, view, fov=30)
        pics.append(earth.render_hdr().radiance)
    seen = pics[0] > 1e-6
    assert seen.sum() > 1000
    assert np.max(np.abs(pics[0] - pics[1])[seen] / pics[0][seen]) < 1e-3



def test_a_thick_planets_larger_multiple_table_renders_as_the_tables_command_reads_it(tmp_path):
    # An optically thick atmosphere's multiple-scattering table has more r rows than its quality level's (16 at
    # draft's 8, precompute.sizes_for): the shader must take the table's size from the table, as the NumPy
    # evaluator does. The 10-bar CO2 planet from 10 km looking 10 deg down, the sun 30 deg up; bound and
    # comparison as in test_shader_radiance_matches_the_tables_command (1%). Measured on llvmpipe: 9e-6.
    scene = Scene("exo-co2-thick", quality="draft", surface=None, off_screen=True, window_size=SIZE)
    try:
        scene.wait_for_tables()
        scene.view_from_ground(latitude=30, altitude=1e4, heading=200, pitch=-10, fov=70)
        scene.set_sun(elevation=30, azimuth=150, latitude=30, longitude=0)
        assert shader_matches_lut(scene, "exo-co2-thick", tmp_path) < 0.01
    finally:
        scene.close()

def test_a_planet_far_away_is_drawn_and_matches_the_tables(earth, tmp_path):
    earth.view_from_space(distance=1e9, latitude=0, longitude=0, fov=1.2)   # the planet: 0.73 deg across
    earth.set_sun(elevation=60, azimuth=90, latitude=0, longitude=0)
    hdr = earth.render_hdr()
    rows, cols = np.meshgrid(np.arange(0, SIZE[1], 3), np.arange(0, SIZE[0], 3), indexing="ij")
    want = tables_radiance(earth, "earth", rows, cols, tmp_path).reshape(rows.shape + (3,))
    got = hdr.radiance[rows, cols]
    seen = want.max(-1) > 0
    assert seen.sum() > 30 and np.array_equal(got.max(-1) > 0, seen)
    assert np.max(np.abs(got - want)[seen] / want[seen]) < 0.01


def test_no_band_on_the_ground_below_the_horizon(earth):
    # The failure of other renderers: S(x) - T(x, y) S(y) computed with inconsistent lookups near the horizon
    # gives a bright or dark band on the ground just below it. Here the ground's radiance, 0.02 to 3 deg below
    # the horizon (0.06 deg per row), must grow toward the horizon with no step larger than the smooth trend's
    # (measured: at most 1.7% per row); a band is a reversal or a jump. Far from the horizon the ground is
    # flat to 1e-4 (table interpolation kinks), hence the 0.999.
    earth.set_sun(elevation=15, azimuth=0, latitude=0, longitude=0)
    earth.view_from_ground(latitude=0, altitude=2.0, heading=180, pitch=-1.5, fov=3.0)
    lum = earth.render_hdr().linear_srgb[..., 1]
    h, w = lum.shape
    d = earth.pixel_directions(np.arange(h), np.full(h, w // 2))
    mu = d @ (earth.camera_location / np.linalg.norm(earth.camera_location))
    ground = np.nonzero(mu < -np.sqrt(1 - (earth.atmosphere.bottom_radius_m / np.linalg.norm(earth.camera_location)) ** 2) - 3e-4)[0]
    column = lum[ground, w // 2]
    assert len(column) > 20
    steps = column[:-1] / column[1:]                # rows from the horizon downward
    assert np.all(steps >= 0.999) and np.all(steps < 1.05), steps


def test_twilight_fades_smoothly_to_night(earth):
    # Sun from 1 to 20 deg below the horizon in 0.5 deg steps, looking at the horizon under it: the sky must
    # darken at every step (no glow frozen past the tables' -18 deg) and by no more than a factor 3 per step
    # (no blocky jumps; the physical decay is ~20-40% per 0.5 deg).
    earth.view_from_ground(latitude=0, altitude=2.0, heading=90, pitch=5, fov=20)
    lum = []
    for el in np.arange(-1.0, -20.5, -0.5):
        earth.set_sun(elevation=el, azimuth=90, latitude=0, longitude=0)
        lum.append(earth.render_hdr().linear_srgb[..., 1].mean())
    lum = np.array(lum)
    assert np.all(lum > 0)
    ratio = lum[1:] / lum[:-1]
    assert np.all(ratio < 1.0) and np.all(ratio > 1 / 3), ratio


def test_the_daylight_sky_has_no_holes(earth):
    # The background must never show through a daylight sky: every sky pixel is lit (measured minimum 60% of
    # the median; bound 20%).
    earth.view_from_ground(latitude=0, altitude=2.0, heading=0, pitch=60, fov=100)
    earth.set_sun(elevation=45, azimuth=200, latitude=0, longitude=0)
    lum = earth.render_hdr().linear_srgb[..., 1]
    assert lum.min() > 0.2 * np.median(lum)


@pytest.fixture(scope="module")
def thick():
    scene = Scene("exo-co2-thick", quality="draft", surface=None, off_screen=True, window_size=SIZE)
    yield scene
    scene.close()


def test_no_banding_in_a_thick_atmosphere(thick):
    # exo-co2-thick (10 bar, tau = 4 at 440 nm): the sky from the zenith to the horizon changes smoothly, row to
    # row (48 rows over 90 deg): no step above 15% (measured at most 6%).
    thick.view_from_ground(latitude=0, altitude=2.0, heading=0, pitch=46, fov=90)
    thick.set_sun(elevation=30, azimuth=0, latitude=0, longitude=0)
    lum = thick.render_hdr().linear_srgb[..., 1]
    column = lum[:, SIZE[0] // 2]
    assert column.min() > 0
    steps = column[1:] / column[:-1]
    assert np.all(np.abs(np.log(steps)) < np.log(1.15)), steps


def test_no_dark_band_below_the_horizon_in_a_thick_atmosphere(thick):
    # In the 10-bar atmosphere the ground a few km away is hidden in haze brighter than it (the horizon's sky),
    # so from 2 m up the ground must brighten toward the horizon at every row over its last 0.3 deg (0.0625 deg
    # per row): the aerial perspective grows with the distance. Measured: each row 3-20% brighter than the one
    # below it. Read from the tables without lookup.ground_row_factor (a camera below the tables' first row took
    # its ground rays' in-scattering as growing with sqrt of their length; single scattering is integrated there
    # since, tables/near_ground.py) it darkened instead, 0.4-12% per row: the dark band below the horizon of
    # other renderers (the gallery's picture of this planet had it).
    thick.set_sun(elevation=15, azimuth=0, latitude=0, longitude=0)
    thick.view_from_ground(latitude=0, altitude=2.0, heading=180, pitch=-1.5, fov=3.0)
    lum = thick.render_hdr().linear_srgb[..., 1]
    h, w = lum.shape
    mu = thick.pixel_directions(np.arange(h), np.full(h, w // 2)) @ (thick.camera_location
                                                                      / np.linalg.norm(thick.camera_location))
    mu_h = -np.sqrt(1 - (thick.atmosphere.bottom_radius_m / np.linalg.norm(thick.camera_location)) ** 2)
    column = lum[np.nonzero(mu < mu_h - 3e-4)[0][:6], w // 2]          # the ground's first 6 rows below it
    assert len(column) == 6
    assert np.all(column[:-1] / column[1:] > 1.0), column[:-1] / column[1:]


def spectral_atmosphere(n=7):
    """exo-mdwarf's composition at ``n`` wavelengths (two texture groups, three read-back passes for n = 7)."""
    import json
    from pathlib import Path
    from planetviz.model.presets import load_dict
    data = json.loads((Path(__file__).parents[1] / "assets/atmospheres/exo-mdwarf.json").read_text())
    data["name"] = "exo-mdwarf-spectral"
    data["wavelengths_nm"] = list(np.linspace(420.0, 700.0, n))
    data["ground_albedo"] = [0.2] * n
    data["mie"]["scattering"]["k"] = [0.0092] * n
    for key in ("g1", "g2", "alpha"):
        data["mie"]["phase"][key] = [data["mie"]["phase"][key][0]] * n
    return load_dict(data)


def test_a_spectral_atmosphere_renders_every_wavelength(tmp_path):
    # 7 wavelengths: the tables span two RGBA groups and the float read-back takes three passes; every
    # wavelength must match the NumPy evaluator (same bound and reason as the 3-wavelength test).
    from planetviz.tables.evaluator import sky_radiance
    atm = spectral_atmosphere()
    scene = Scene(atm, quality="draft", surface=None, off_screen=True, window_size=SIZE)
    try:
        scene.view_from_ground(latitude=0, altitude=2.0, heading=90, pitch=3, fov=60)
        scene.set_sun(elevation=12, azimuth=100, latitude=0, longitude=0)
        hdr = scene.render_hdr()
        rows, cols = np.meshgrid(np.arange(1, SIZE[1], 4), np.arange(1, SIZE[0], 5), indexing="ij")
        keep = away_from_sun(scene, rows, cols).ravel()
        dirs = scene.pixel_directions(rows, cols).reshape(-1, 3)
        want, _ = sky_radiance(scene.planet.tables, atm, np.tile(scene.camera_location, (len(dirs), 1)), dirs,
                              scene.sun_direction)
    finally:
        scene.close()
    got = hdr.radiance[rows, cols].reshape(-1, 7)
    assert hdr.radiance.shape[-1] == 7 and hdr.linear_srgb.shape[-1] == 3
    assert np.max(np.abs(got - want)[keep] / want[keep]) < 0.01


def test_the_terminator_seen_from_space_has_no_step(earth):
    # Across the terminator the ground darkens through the twilight zone by up to a factor 6 per pixel here
    # (1 pixel ~ 0.6 deg of arc), smoothly: each step (in log) is at most twice the larger of its two
    # neighbours (measured at most 1.3 times), plus 0.2 for the flat day side. A seam is an isolated jump.
    earth.view_from_space(distance=1.6e7, latitude=0, longitude=0, fov=40)
    earth.set_sun(elevation=0, azimuth=90, latitude=0, longitude=0)  # the terminator through the centre
    lum = earth.render_hdr().linear_srgb[..., 1]
    h, w = lum.shape
    row = lum[h // 2, w // 4: 3 * w // 4]
    lit = row[row > 0]
    steps = np.abs(np.diff(np.log(lit)))
    assert len(lit) > 10
    neighbours = np.maximum(steps[:-2], steps[2:])
    assert np.all(steps[1:-1] < 2 * neighbours + 0.2), steps


@pytest.mark.parametrize("tone_mapping", ["exponential", "filmic"])
def test_the_window_shows_the_tone_mapped_linear_radiance(earth, tone_mapping):
    # The 8-bit window is the float linear sRGB (render_hdr) times the exposure, tone-mapped and sRGB-encoded:
    # checked against the same steps in NumPy (colour-science's sRGB encoding). Bound: 1.5/255 (8-bit
    # rounding and float32).
    import colour
    earth.view_from_ground(latitude=0, heading=90, pitch=5, fov=60)
    earth.set_sun(elevation=4, azimuth=80, latitude=0, longitude=0)
    earth.settings.tone_mapping = tone_mapping
    try:
        x = np.maximum(earth.render_hdr().linear_srgb, 0) * earth.settings.exposure
        shown = earth.screenshot()[..., :3] / 255.0
    finally:
        earth.settings.tone_mapping = "exponential"
    if tone_mapping == "exponential":
        mapped = 1 - np.exp(-x)
    else:
        mapped = np.clip(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0, 1)
    want = colour.cctf_encoding(np.clip(mapped, 0, 1), function="sRGB")
    assert np.abs(shown - want).max() < 1.5 / 255
