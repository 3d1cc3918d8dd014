"""The GLSL sources, shipped as package data of planetviz (read by planetviz.render.shaders)."""
