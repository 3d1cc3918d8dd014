"""planetviz desktop app entry point.

The window, widgets and rendering come with the rendering and app issues; until then this runs the
command line (``python app.py sky``, ``python app.py radiance ...``).
"""
import sys

from planetviz.cli import main

if __name__ == "__main__":
    sys.exit(main())
