"""A Meshcat "window" in memory: records a scene and returns meshcat's own static page, no socket."""

from __future__ import annotations

from typing import Any

from springbalance.errors import SpringBalanceError
from springbalance.viz.meshcat_import import import_meshcat


class SceneRecorder:
    """A meshcat "window" that keeps the scene in memory: no server, no socket.

    It hands every command to meshcat's own server logic (the scene tree of
    ``ZMQWebSocketBridge``), so :meth:`get_scene` returns exactly the static page a
    meshcat server would (``Visualizer.static_html()``).
    """

    def __init__(self) -> None:
        servers = import_meshcat().servers
        ZMQWebSocketBridge = servers.zmqserver.ZMQWebSocketBridge
        bridge = ZMQWebSocketBridge.__new__(ZMQWebSocketBridge)  # the logic only, no sockets
        bridge.tree = servers.tree.SceneTree()
        bridge.websocket_pool = set()
        bridge.zmq_socket = _Reply()
        self._bridge = bridge
        self.web_url = None

    @property
    def tree(self) -> Any:
        """meshcat's scene tree (nodes hold the msgpack-encoded objects, transforms, animations)."""
        return self._bridge.tree

    def send(self, command: Any) -> None:
        """Hand a meshcat command to the scene tree, as a server does with one from its socket."""
        import umsgpack

        data = command.lower()
        self._bridge.handle_zmq([data["type"].encode("utf-8"), data["path"].encode("utf-8"), umsgpack.packb(data)])

    def get_scene(self) -> str:
        """meshcat's self-contained static page of the scene recorded so far."""
        self._bridge.handle_zmq([b"get_scene"])
        return self._bridge.zmq_socket.reply.decode("utf-8")

    def get_image(self) -> None:  # pragma: no cover - needs a browser
        raise SpringBalanceError("a recorded scene has no browser to take an image from; use show() or scene.html")


class _Reply:
    reply = b""

    def send(self, data: bytes) -> None:
        self.reply = data
