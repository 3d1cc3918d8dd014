"""The atmosphere model: the file format and its checks (:mod:`.atmosphere`), the presets, the advanced mode's
physical quantities (:mod:`.advanced`), the optical properties (:mod:`.optics`), planet-centred geometry,
query files and colour. Everything else reads an :class:`~planetviz.model.atmosphere.Atmosphere` from here."""
