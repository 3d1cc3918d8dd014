"""planetviz desktop app: ``python app.py`` opens a window showing Earth from orbit: the Qt window with its side
panel (planetviz/app/qt_window.py; needs ``pip install .[app]``), or with ``--no-qt`` (or without Qt) the PyVista
window with slider widgets (planetviz/app/window.py).

With an output option it renders off-screen instead (no display needed), with the options of
``planetviz render``:

    python app.py --preset mars --view ground --sun-elevation 3 --sun-azimuth 0 --size 1920x1080 \\
                  --screenshot out.png [--exr out.exr]
"""
import argparse
import sys
from pathlib import Path

from planetviz.app.render_options import SITE, add_render_options, place_site_and_sun, run_render, wants_output


def main(argv=None):
    parser = argparse.ArgumentParser(prog="app.py", description="planetviz: planets with physical atmospheres")
    add_render_options(parser)
    parser.add_argument("--mode", choices=("standard", "advanced"), default="standard", help="the window's sliders")
    parser.add_argument("--no-qt", action="store_true", help="the PyVista window with slider widgets, not Qt's")
    args = parser.parse_args(argv)
    try:
        if wants_output(args):
            return run_render(args)
        place_site_and_sun(args)
        site = (args.latitude, args.longitude) if args.site else SITE
        atmosphere_file = args.atmosphere if Path(args.atmosphere).is_file() else None
        if not args.no_qt:
            try:
                from planetviz.app.qt_window import run_qt
            except ImportError as exc:
                print(f"app.py: no Qt ({exc}): the PyVista window instead (pip install .[app] for Qt's)",
                      file=sys.stderr)
            else:
                return run_qt(atmosphere=args.atmosphere, quality=args.quality, method=args.method,
                              shading=args.shading or "auto", exposure=args.exposure,
                              tone_mapping=args.tone_mapping, tables=args.tables, site=site, time=args.time,
                              sun=None if args.time else (args.sun_elevation, args.sun_azimuth), mode=args.mode,
                              atmosphere_file=atmosphere_file)
        from planetviz.app.window import run
        from planetviz.render import Scene
        scene = Scene(args.atmosphere, quality=args.quality, window_size=args.size, method=args.method,
                      shading=args.shading or "auto", exposure=args.exposure, tone_mapping=args.tone_mapping,
                      tables=args.tables)
        scene.set_sun(elevation=args.sun_elevation, azimuth=args.sun_azimuth)
        run(scene, mode=args.mode, atmosphere_file=atmosphere_file, site=site)
        return 0
    except (ValueError, OSError) as exc:
        print(f"app.py: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
