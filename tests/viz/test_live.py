"""The live server: 127.0.0.1 only, stops cleanly on Ctrl-C, a busy port fails in one line; show()."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

from cli_helpers import until_ctrl_c
from springbalance.results.result import DesignResult
from springbalance.viz import scene as viz


# ---------------------------------------------------------------------- must hold 2: live server
def _listening_sockets(pid: int) -> list[tuple[str, int]]:
    """(address, port) of every listening TCP socket of process ``pid`` (Linux /proc)."""
    inodes = set()
    for fd in Path(f"/proc/{pid}/fd").iterdir():
        try:
            target = os.readlink(fd)
        except OSError:
            continue
        if target.startswith("socket:["):
            inodes.add(target[8:-1])
    found = []
    for table, width in (("/proc/net/tcp", 8), ("/proc/net/tcp6", 32)):
        if not os.path.exists(table):
            continue
        for line in Path(table).read_text().splitlines()[1:]:
            fields = line.split()
            if fields[3] != "0A" or fields[9] not in inodes:  # 0A = LISTEN
                continue
            address, port = fields[1].split(":")
            raw = bytes.fromhex(address)
            if width == 8:
                text = socket.inet_ntop(socket.AF_INET, raw[::-1])
            else:
                text = socket.inet_ntop(socket.AF_INET6, b"".join(raw[i : i + 4][::-1] for i in range(0, 16, 4)))
            found.append((text, int(port, 16)))
    return found


def _children(pid: int) -> list[int]:
    children = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1]) == pid:
                    children.append(int(entry.name))
            except (OSError, IndexError, ValueError):
                continue
    return children


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _outside_address() -> str | None:
    """An address of this machine other than loopback, if it has one."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        try:
            probe.connect(("192.0.2.1", 9))  # TEST-NET address: nothing is sent
            address = probe.getsockname()[0]
        except OSError:
            return None
    return None if address.startswith("127.") else address


@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads listening sockets from /proc")
def test_view_serves_on_loopback_only_and_stops_cleanly_on_ctrl_c(design_file):
    port = _free_port()
    servers = []

    def check(process, first):
        assert f"http://127.0.0.1:{port}/static/" in first, first
        servers.extend(_children(process.pid))
        assert len(servers) == 1
        sockets = _listening_sockets(servers[0]) + _listening_sockets(process.pid)
        assert (("127.0.0.1", port) in sockets) and len(sockets) >= 2, sockets  # web page and ZeroMQ
        assert all(address == "127.0.0.1" for address, _ in sockets), sockets
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/static/", timeout=10) as response:
            assert response.status == 200 and b"meshcat" in response.read().lower()
        outside = _outside_address()
        if outside is not None:
            with pytest.raises(OSError):
                socket.create_connection((outside, port), timeout=2).close()

    code, out, err = until_ctrl_c(["view", str(design_file), "--port", str(port), "--frames", "8"], check)
    # a design that fails a check is shown, then exits with 3 (springbalance.cli.outcome)
    passes = DesignResult.load(design_file).ok
    assert code in ((0 if passes else 3), 130), (code, err)
    assert "Traceback" not in err and "Traceback" not in out
    assert "stopped" in out
    deadline = time.monotonic() + 10
    while any(Path(f"/proc/{pid}").exists() and "zombie" not in _state(pid) for pid in servers):
        assert time.monotonic() < deadline, "the meshcat server outlived `springbalance view`"
        time.sleep(0.1)


def _state(pid: int) -> str:
    try:
        return "zombie" if (Path(f"/proc/{pid}") / "stat").read_text().rsplit(")", 1)[1].split()[0] == "Z" else "alive"
    except OSError:
        return "zombie"


@pytest.mark.slow
def test_view_on_a_busy_port_fails_in_one_line(design_file):
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        completed = subprocess.run(
            [sys.executable, "-m", "springbalance.cli", "view", str(design_file), "--port", str(port)],
            capture_output=True,
            text=True,
            timeout=60,
        )
    assert completed.returncode == 2
    lines = completed.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("springbalance: error: the meshcat server exited"), lines
    assert "Traceback" not in completed.stderr


def test_show_draws_on_a_local_server_and_static_needs_none(design):
    static = design.show(static=True, frames_per_joint=8)
    assert isinstance(static, viz.StaticScene) and "srcdoc=" in static._repr_html_()
    live = design.show(frames_per_joint=8)
    try:
        assert live.url.startswith("http://127.0.0.1:")
        assert f'src="{live.url}"' in live._repr_html_()
        with urllib.request.urlopen(live.url, timeout=10) as response:
            assert response.status == 200
        sockets = _listening_sockets(live.server.process.pid) if sys.platform.startswith("linux") else []
        assert all(address == "127.0.0.1" for address, _ in sockets), sockets
    finally:
        live.server.stop()
    assert not live.server.running
