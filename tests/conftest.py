"""Test configuration: off-screen rendering through OSMesa, set before VTK is imported."""
import os

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
