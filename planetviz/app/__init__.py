"""The user's entry points: the command line (:mod:`.cli`), its rendering options shared with ``app.py``
(:mod:`.render_options`) and the PyVista window with its sliders (:mod:`.window`). They only wire the layers
below (render -> tables -> model) to the user's options."""
