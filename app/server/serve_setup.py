"""Setup script for ``panel serve app/main.py --setup app/server/serve_setup.py``: the app's websocket handler
(:mod:`ringlab.server.socket_guard`) for the server about to be made and its pages built one per turn
(:func:`ringlab.server.joining.order_builds`); ``ringlab serve`` does this itself."""
from ringlab.server import joining, socket_guard

socket_guard.install()
joining.order_builds()
