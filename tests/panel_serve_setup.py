"""Setup script of the test harness's ``panel serve app/main.py --setup tests/panel_serve_setup.py`` (one process).

``ringlab serve`` routes the app's websocket handler (:class:`ringlab.server.socket_guard.AppWSHandler`) through
Tornado's public ``add_handlers`` on the server it builds itself.  ``panel serve`` makes its server inside Bokeh
and offers no public way to reach it, so the package serves ``panel serve`` with Bokeh's handler.  The browser
tests that run ``panel serve`` check the app's handler at work (no traceback or "Failed sending" line when a
page leaves mid-stream, a closed tab's runs freed at once): here, in the test harness only, the handler is put
where Bokeh reads an application's routes when the server is made (Panel's own module does the same), which is
Bokeh's private list and must run before the server is made (one process: Panel runs this before).
"""
from bokeh.server import urls

from ringlab.server import joining, socket_guard

for i, route in enumerate(urls.per_app_patterns):
    if route[0] == r"/ws" and issubclass(socket_guard.AppWSHandler, route[1]):
        urls.per_app_patterns[i] = (route[0], socket_guard.AppWSHandler, *route[2:])
        break
else:
    raise RuntimeError("this Bokeh has no /ws route served by Panel's handler")
socket_guard.install()
joining.order_builds()  # the pages built one per turn, as ringlab serve has them
