"""ringlab web app (Panel): interactive views of the ring model of Lehmann, Schmidt & Salo (2017).

Modules:

- :mod:`app.controls`      settings shared by the views (``param.Parameterized``, no widgets)
- :mod:`app.linear_model`  linear-theory curves and numbers for the current settings (no widgets)
- :mod:`app.linear_view`   the "Linear theory" tab (a ``pn.viewable.Viewer``)
- :mod:`app.main`          assembles the tabs into a template and serves it (``panel serve app/main.py``)

The app imports :mod:`ringcore`; ringcore never imports the app, panel, param or holoviews.
"""
