"""Preset atmospheres, spectral data and surface textures, shipped as package data of planetviz
(read through planetviz.resources)."""
