"""Test configuration: off-screen rendering through OSMesa (set before VTK is imported), and a table cache
of the test run's own, so that tests never read or fill the user's ~/.cache/planetviz."""
import os
import tempfile

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
os.environ["PLANETVIZ_CACHE"] = tempfile.mkdtemp(prefix="planetviz-test-cache-")
