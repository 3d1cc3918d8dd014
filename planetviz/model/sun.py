"""The Sun's place in Earth's sky for a site and a time.

NREL's Solar Position Algorithm (Reda and Andreas, "Solar position algorithm for solar radiation applications",
2004; 0.0003 deg from the year -2000 to 6000) through pvlib's ``spa_python``: the geometric (topocentric,
unrefracted) elevation above the horizon and the azimuth from north through east, in degrees. No refraction:
the renderer bends no rays, so the picture's sun sits where the geometry puts it.

Example
-------
>>> from planetviz.model.sun import parse_time, sun_position
>>> el, az = sun_position(48.85, 2.35, parse_time("2026-06-21T12:00:00+02:00"))
>>> round(el, 1), round(az, 1)
(56.3, 128.8)
"""
from __future__ import annotations

import numpy as np

from .limits import check_number

#: The ranges of a site [deg].
SITE_LIMITS = {"latitude": (-90.0, 90.0), "longitude": (-180.0, 360.0)}


def parse_site(text: str) -> tuple:
    """(latitude, longitude) [deg] from ``"LAT,LON"`` (north and east positive)."""
    try:
        lat, lon = (float(v) for v in str(text).split(","))
    except ValueError:
        raise ValueError(f"site: LAT,LON in degrees (north and east positive), e.g. 48.85,2.35, got {text!r}") from None
    return (check_number(lat, "site latitude", *SITE_LIMITS["latitude"]),
            check_number(lon, "site longitude", *SITE_LIMITS["longitude"]))


def parse_time(text: str):
    """A UTC ``pandas.Timestamp`` from ISO 8601 (``2026-06-21T12:00``, with an offset or ``Z``; without one, UTC)
    or ``now``."""
    import pandas as pd
    try:
        stamp = pd.Timestamp.now(tz="UTC") if str(text).strip().lower() == "now" else pd.Timestamp(text)
    except (ValueError, TypeError):
        raise ValueError(f"time: ISO 8601, e.g. 2026-06-21T12:00:00+02:00 (UTC without an offset) or now, "
                         f"got {text!r}") from None
    if stamp is pd.NaT:
        raise ValueError(f"time: ISO 8601 or now, got {text!r}")
    return stamp.tz_localize("UTC") if stamp.tzinfo is None else stamp.tz_convert("UTC")


def time_steps(start: str, stop: str, step: str) -> list:
    """UTC times from ``start`` to ``stop`` (ISO 8601, both included when the steps land on it) every ``step``
    (a duration: ``10min``, ``1h``, ``PT10M``)."""
    import pandas as pd
    t0, t1 = parse_time(start), parse_time(stop)
    try:
        dt = pd.Timedelta(step)
    except ValueError:
        raise ValueError(f"time-lapse STEP: a duration such as 10min, 1h or PT10M, got {step!r}") from None
    if dt <= pd.Timedelta(0) or t1 < t0:
        raise ValueError(f"time-lapse: STEP must be positive and STOP not before START, got {start} {stop} {step}")
    count = int((t1 - t0) // dt) + 1
    if count > 100_000:
        raise ValueError(f"time-lapse: at most 100000 frames, got {count}")
    return [t0 + k * dt for k in range(count)]


def sun_position(latitude: float, longitude: float, time) -> tuple:
    """(elevation, azimuth) [deg] of the Sun's centre seen from a site at ``time`` (a UTC Timestamp,
    :func:`parse_time`): geometric, azimuth from north through east in [0, 360)."""
    import pandas as pd
    from pvlib.solarposition import spa_python
    check_number(latitude, "site latitude", *SITE_LIMITS["latitude"])
    check_number(longitude, "site longitude", *SITE_LIMITS["longitude"])
    position = spa_python(pd.DatetimeIndex([time]), latitude, longitude, delta_t=None)
    return float(position["elevation"].iloc[0]), float(np.mod(position["azimuth"].iloc[0], 360.0))
