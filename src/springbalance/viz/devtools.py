"""A page in headless Chromium driven through the DevTools protocol (:class:`PageSession`): run JavaScript in it,
read what it computed, take screenshots. No network: the protocol runs over a pair of pipes
(``--remote-debugging-pipe``, messages are JSON texts ended by a NUL byte), not a port.

This is how the tests move a scene's pose slider and read the scene graph and the overlay back
(:mod:`springbalance.viz.browser` only renders a page once into a PNG). Chromium is found as
:func:`springbalance.viz.browser.find_chromium` finds it; WebGL runs on SwiftShader.
"""

from __future__ import annotations

import base64
import fcntl
import json
import os
import re
import selectors
import subprocess
import tempfile
import time
from pathlib import Path
from types import TracebackType
from typing import Any

from springbalance.viz.browser import WINDOW, BrowserError, chromium_command, find_chromium

#: attempts to remove the browser's profile folder after it stopped, 0.2 s apart
PROFILE_REMOVALS = 10


class PageSession:
    """Headless Chromium showing one page, driven over the DevTools protocol.

    Use as a context manager (the browser is stopped at the end)::

        with PageSession("scene.html") as page:
            page.wait_for("window.springbalancePoses && springbalancePoses.ready()")
            frame = page.evaluate("springbalancePoses.frame()")

    Args:
        url: a page (a path, opened as ``file://``, or a URL).
        window: the viewport (width, height) [px].
        timeout: seconds to wait for any one answer of the browser.
    """

    def __init__(self, url: str | Path, window: tuple[int, int] = WINDOW, timeout: float = 60.0) -> None:
        chromium = find_chromium()
        if chromium is None:
            raise BrowserError("Chromium is not installed")
        self.timeout = timeout
        self._profile = tempfile.TemporaryDirectory(prefix="springbalance-devtools-", ignore_cleanup_errors=True)
        command = chromium_command(chromium, Path("unused"), Path("unused.png"), Path(self._profile.name), window)
        command = [part for part in command[:-1] if not part.startswith(("--screenshot", "--virtual-time-budget"))]
        command += ["--remote-debugging-pipe", "about:blank"]
        to_child, self._write = os.pipe()  # the browser reads commands on its fd 3 ...
        self._read, from_child = os.pipe()  # ... and writes answers on its fd 4

        def pipes_at_3_and_4() -> None:  # in the child, before exec; via high numbers, as either may be 3 or 4
            high_in, high_out = fcntl.fcntl(to_child, fcntl.F_DUPFD, 10), fcntl.fcntl(from_child, fcntl.F_DUPFD, 10)
            os.dup2(high_in, 3)
            os.dup2(high_out, 4)

        self.process = subprocess.Popen(
            command,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            # fds 3 and 4 are made in preexec_fn, which runs before close_fds would close them; Python's own
            # descriptors are not inheritable (PEP 446), so nothing else leaks into the browser
            close_fds=False,
            preexec_fn=pipes_at_3_and_4,
        )
        os.close(to_child)
        os.close(from_child)
        self._buffer, self._next_id = b"", 0
        #: the protocol's events received so far (``{"method", "params", "sessionId"}``)
        self.events: list[dict[str, Any]] = []
        self._selector = selectors.DefaultSelector()
        self._selector.register(self._read, selectors.EVENT_READ)
        try:
            targets = self.send("Target.getTargets")["targetInfos"]
            page = next(target for target in targets if target["type"] == "page")
            self._session = self.send("Target.attachToTarget", targetId=page["targetId"], flatten=True)["sessionId"]
            self.call("Page.enable")
            self.call("Runtime.enable")
            # the viewport is the window's size, as for browser.screenshot (a headless window keeps room for chrome)
            self.call(
                "Emulation.setDeviceMetricsOverride",
                width=window[0],
                height=window[1],
                deviceScaleFactor=1,
                mobile=False,
            )
            self.navigate(url)
        except BaseException:
            self.close()
            raise

    # ---------------------------------------------------------------- the protocol
    def send(self, method: str, session: str | None = None, **params: Any) -> dict[str, Any]:
        """Send one command (to the browser, or to the page ``session``) and return its result."""
        self._next_id += 1
        message: dict[str, Any] = {"id": self._next_id, "method": method, "params": params}
        if session is not None:
            message["sessionId"] = session
        os.write(self._write, json.dumps(message).encode("utf-8") + b"\0")
        deadline = time.monotonic() + self.timeout
        while True:
            answer = self._receive(deadline)
            if answer.get("id") == self._next_id:
                if "error" in answer:
                    raise BrowserError(f"DevTools {method}: {answer['error'].get('message')}")
                result: dict[str, Any] = answer.get("result", {})
                return result
            if "method" in answer:
                self.events.append(answer)

    def call(self, method: str, **params: Any) -> dict[str, Any]:
        """Send a command to the page."""
        return self.send(method, session=self._session, **params)

    def _receive(self, deadline: float) -> dict[str, Any]:
        while b"\0" not in self._buffer:
            remaining = deadline - time.monotonic()
            if remaining <= 0 or not self._selector.select(remaining):
                raise BrowserError(f"Chromium did not answer within {self.timeout:g} s")
            chunk = os.read(self._read, 1 << 20)
            if not chunk:
                raise BrowserError("Chromium closed the DevTools pipe")
            self._buffer += chunk
        text, self._buffer = self._buffer.split(b"\0", 1)
        message: dict[str, Any] = json.loads(text)
        return message

    # ---------------------------------------------------------------- the page
    def navigate(self, url: str | Path) -> None:
        """Open ``url`` (a path opens as ``file://``) and wait for its load event (a change of the fragment
        alone loads nothing: open ``about:blank`` first)."""
        address = str(url) if re.match(r"[a-z][a-z0-9+.-]*:", str(url)) else Path(url).resolve().as_uri()
        self.events.clear()
        self.call("Page.navigate", url=address)
        deadline = time.monotonic() + self.timeout
        while not any(event.get("method") == "Page.loadEventFired" for event in self.events):
            answer = self._receive(deadline)
            if "method" in answer:
                self.events.append(answer)

    def evaluate(self, expression: str) -> Any:
        """The value of the JavaScript ``expression`` in the page (promises awaited; JSON-able values)."""
        result = self.call("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in result:
            details = result["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text")
            raise BrowserError(f"JavaScript error in {expression[:80]!r}: {text}")
        return result["result"].get("value")

    def wait_for(self, expression: str, timeout: float | None = None, interval: float = 0.1) -> Any:
        """Evaluate ``expression`` until it is truthy; return its value (BrowserError after ``timeout`` s)."""
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        while True:
            value = self.evaluate(expression)
            if value:
                return value
            if time.monotonic() > deadline:
                raise BrowserError(f"{expression!r} still false after {timeout or self.timeout:g} s")
            time.sleep(interval)

    def screenshot(self, path: str | Path) -> Path:
        """Save a PNG of the viewport to ``path`` (after the next animation frame is drawn)."""
        self.evaluate("new Promise(resolve => requestAnimationFrame(() => requestAnimationFrame(resolve)))")
        data = self.call("Page.captureScreenshot", format="png")["data"]
        path = Path(path)
        path.write_bytes(base64.b64decode(data))
        return path

    def close(self) -> None:
        """Stop the browser (idempotent)."""
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        for fd in (self._read, self._write):
            try:
                os.close(fd)
            except OSError:
                pass
        self._selector.close()
        self._remove_profile()

    def _remove_profile(self) -> None:
        """Remove the browser's profile folder. Chromium's helper processes (renderer, crash handler) can outlive
        the browser by a moment and still write there: tried :data:`PROFILE_REMOVALS` times, a moment apart."""
        for _ in range(PROFILE_REMOVALS):
            self._profile.cleanup()  # ignores errors: what a helper wrote meanwhile stays
            if not os.path.exists(self._profile.name):
                return
            time.sleep(0.2)

    def __enter__(self) -> PageSession:
        return self

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        self.close()
