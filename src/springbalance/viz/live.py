"""A live scene: a Meshcat server in a child process on 127.0.0.1 only (:mod:`springbalance.viz.server`), and the
scene's own page on it (legend, name labels placed apart, anchor regions' checkbox and pose slider, :func:`publish_scene`)."""

from __future__ import annotations

import atexit
import contextlib
import html
import io
import selectors
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from springbalance.errors import SpringBalanceError
from springbalance.viz.design_scene import DesignScene
from springbalance.viz.meshcat_import import import_meshcat
from springbalance.viz.pose_data import scene_pose_data
from springbalance.viz.pose_slider import live_page


class MeshcatServer:
    """A meshcat server in a child process, listening on 127.0.0.1 only.

    Attributes:
        web_url: the viewer's address (``http://127.0.0.1:<port>/static/``).
        zmq_url: where clients send drawing commands (``tcp://127.0.0.1:<port>``).
        process: the child process.
    """

    def __init__(self, port: int | None = None, timeout: float = 30.0) -> None:
        # run the module as a script: it needs meshcat and tornado only, not the whole package
        #: the folder the server serves at /springbalance/ (:meth:`publish`), removed by :meth:`stop`
        self.pages = tempfile.TemporaryDirectory(prefix="springbalance-pages-")
        command = [sys.executable, "-u", str(Path(__file__).with_name("server.py")), "--pages", self.pages.name]
        if port is not None:
            command += ["--port", str(int(port))]
        self._stderr = tempfile.TemporaryFile()
        self.process = subprocess.Popen(
            command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=self._stderr, start_new_session=True
        )
        atexit.register(self.stop)
        urls: dict[str, str] = {}
        deadline = time.monotonic() + timeout
        stdout = self.process.stdout
        if stdout is None:  # never: stdout is a pipe
            raise SpringBalanceError("the meshcat server's output is not a pipe")
        with selectors.DefaultSelector() as selector:
            selector.register(stdout, selectors.EVENT_READ)
            while len(urls) < 2:
                remaining = deadline - time.monotonic()
                if remaining <= 0 or not selector.select(remaining):
                    self.stop()
                    raise SpringBalanceError(f"the meshcat server did not start within {timeout:g} s")
                line = stdout.readline().decode("utf-8", "replace").strip()
                if not line:
                    with contextlib.suppress(subprocess.TimeoutExpired):
                        self.process.wait(5)
                    message = self._error_text()
                    self.stop()
                    raise SpringBalanceError(f"the meshcat server exited: {message}")
                key, _, value = line.partition("=")
                if key in ("zmq_url", "web_url"):
                    urls[key] = value
        self.zmq_url, self.web_url = urls["zmq_url"], urls["web_url"]

    def _error_text(self) -> str:
        self._stderr.seek(0)
        text = self._stderr.read().decode("utf-8", "replace").strip().splitlines()
        return text[-1] if text else "no message"

    def publish(self, page: str, name: str = "index.html") -> str:
        """Serve the HTML ``page`` at ``/springbalance/<name>`` on this server; returns its address."""
        if "/" in name or "\\" in name or name.startswith("."):
            raise SpringBalanceError(f"a page's name is a plain file name, got {name!r}")
        (Path(self.pages.name) / name).write_text(page, encoding="utf-8")
        return self.web_url.removesuffix("static/") + "springbalance/" + ("" if name == "index.html" else name)

    def visualizer(self) -> Any:
        """A ``meshcat.Visualizer`` connected to this server."""
        meshcat = import_meshcat()
        with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints the URL itself
            return meshcat.Visualizer(zmq_url=self.zmq_url)

    @property
    def running(self) -> bool:
        """True while the server's process runs."""
        return self.process.poll() is None

    def stop(self) -> None:
        """Stop the server (idempotent)."""
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(5)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        if self.process.stdout is not None and not self.process.stdout.closed:
            self.process.stdout.close()
        self._stderr.close()
        self.pages.cleanup()

    def __repr__(self) -> str:
        return f"MeshcatServer({self.web_url!r}, running={self.running})"


_SERVER: MeshcatServer | None = None


def local_server(port: int | None = None) -> MeshcatServer:
    """The session's meshcat server on 127.0.0.1 (started on first use, stopped at exit)."""
    global _SERVER
    if _SERVER is None or not _SERVER.running:
        _SERVER = MeshcatServer(port=port)
    return _SERVER


def publish_scene(server: MeshcatServer, scene: DesignScene) -> str:
    """Serve the page of ``scene`` drawn on ``server`` (meshcat's viewer with the colour legend, the name labels
    placed apart as on the static page, the anchor regions' checkbox and the pose slider,
    :func:`~springbalance.viz.pose_slider.live_page`) at ``/springbalance/``; returns its address."""
    return server.publish(live_page(scene_pose_data(scene), scene.legend_html() + scene.labels()))


class LiveScene:
    """A design drawn on a running meshcat server. In Jupyter it shows inline (an iframe).

    ``page_url``: the scene's own page on the server (:func:`publish_scene`: legend and pose slider), else
    meshcat's viewer is shown."""

    def __init__(self, scene: DesignScene, server: MeshcatServer, visualizer: Any, page_url: str | None = None) -> None:
        self.scene, self.server, self.visualizer, self.page_url = scene, server, visualizer, page_url

    @property
    def url(self) -> str:
        """The scene's address on the server: its page with the pose slider, else meshcat's viewer."""
        return self.page_url or self.server.web_url

    def _repr_html_(self) -> str:
        return (
            f'<div style="position:relative;height:480px">'
            f"{'' if self.page_url else self.scene.legend_html(position='absolute')}"
            f'<iframe src="{html.escape(self.url)}" style="width:100%;height:100%;border:none"></iframe></div>'
        )

    def __repr__(self) -> str:
        return f"LiveScene({self.url!r}, {self.scene.size} frames)"
