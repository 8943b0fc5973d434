"""Setup script for ``panel serve app/main.py --setup app/server/serve_setup.py``: the app's websocket handler
(:mod:`ringlab.server.socket_guard`) for the server about to be made (``ringlab serve`` does this itself)."""
from ringlab.server import socket_guard

socket_guard.install()
