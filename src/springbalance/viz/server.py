"""A meshcat server that listens on 127.0.0.1 only.

meshcat's own server (``meshcat-server``, or ``meshcat.Visualizer()`` without a URL) binds
its ZeroMQ socket to 127.0.0.1 but its web server to every interface. This one binds both
to the loopback interface, so the scene is not reachable from other machines.

With ``--pages DIR`` it also serves the files of ``DIR`` at ``/springbalance/`` (the scene's page with
its pose slider, :func:`springbalance.viz.pose_slider.live_page`), on the same loopback address.

Run as ``python -m springbalance.viz.server [--port PORT] [--pages DIR]``; it prints
``zmq_url=...`` and ``web_url=...`` on two lines, then serves until it gets SIGTERM or
SIGINT, or until the process that started it is gone.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from tornado.httpserver import HTTPServer
    from tornado.web import Application

HOST = "127.0.0.1"


def main(argv: list[str] | None = None) -> int:
    import tornado.ioloop
    from meshcat.servers.zmqserver import StaticFileHandlerNoCache, ZMQWebSocketBridge

    class LoopbackBridge(ZMQWebSocketBridge):
        """meshcat's bridge whose web application listens on 127.0.0.1 only."""

        def make_app(self) -> Application:
            app = super().make_app()
            if args.pages:  # springbalance's own pages (the scene with its pose slider), from that folder
                pages = {"path": args.pages, "default_filename": "index.html"}
                app.add_handlers(".*", [(r"/springbalance/(.*)", StaticFileHandlerNoCache, pages)])
            listen = app.listen

            def listen_on_loopback(port: int, address: str | None = None, **kwargs: Any) -> HTTPServer:
                return listen(port, address=HOST, **kwargs)

            app.listen = listen_on_loopback
            return app

    parser = argparse.ArgumentParser(prog="python -m springbalance.viz.server", description=__doc__.split("\n")[0])
    parser.add_argument("--port", type=int, default=None, help="web port (default: the first free one from 7000)")
    parser.add_argument("--pages", default=None, help="serve the files of this folder at /springbalance/")
    args = parser.parse_args(argv)

    parent = os.getppid()
    bridge = LoopbackBridge(host=HOST, port=args.port)
    print(f"zmq_url={bridge.zmq_url}", flush=True)
    print(f"web_url={bridge.web_url}", flush=True)
    # nobody reads our output from now on: a full pipe must never block the server
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    os.dup2(devnull, 2)

    loop = tornado.ioloop.IOLoop.current()

    def stop(*_: object) -> None:
        loop.add_callback_from_signal(loop.stop)

    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)

    def watch_parent() -> None:
        if os.getppid() != parent:  # the process that started us is gone
            loop.stop()

    tornado.ioloop.PeriodicCallback(watch_parent, 1000).start()
    loop.start()
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
