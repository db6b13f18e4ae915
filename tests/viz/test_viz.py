"""The Meshcat scene: helix geometry, end points against the model, colours, the static page
(rendered for real in headless Chromium), and the live server (127.0.0.1 only, Ctrl-C)."""

from __future__ import annotations

import colorsys
import os
import re
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import umsgpack

import springbalance as sb
from springbalance.model import sweeps
from springbalance.viz import browser
from springbalance.viz import arm, colors, helix
from springbalance.viz.recorder import SceneRecorder
from springbalance.viz import scene as viz
from springbalance.viz.meshcat_import import import_meshcat

meshcat = import_meshcat()   # silences meshcat's import-time deprecation warning
from meshcat.servers.tree import walk  # noqa: E402
from scene_helpers import LINK1_RGB, URDF, two_link_design, ur5_design


@pytest.fixture(scope="module")
def design():
    return two_link_design()


@pytest.fixture(scope="module")
def design_file(design, tmp_path_factory):
    return design.save(tmp_path_factory.mktemp("design") / "design.json")


# ---------------------------------------------------------------------- helix geometry
def test_helix_centerline_has_the_coils_and_ends_on_the_axis():
    line = helix.helix_centerline(coils=7, coil_radius=0.02, lead=0.1, points_per_coil=30)
    np.testing.assert_array_equal(line[0], [0, 0, 0])
    np.testing.assert_array_equal(line[-1], [0, 0, 1])
    coil = line[1:-1]
    np.testing.assert_allclose(np.hypot(coil[:, 0], coil[:, 1]), 0.02, rtol=1e-12)       # the coil radius
    assert np.all(np.diff(line[:, 2]) > 0)                                                # it always advances
    turns = np.unwrap(np.arctan2(coil[:, 1], coil[:, 0]))
    assert (turns[-1] - turns[0]) / (2 * np.pi) == pytest.approx(7.0)                    # 7 coils
    assert coil[0, 2] == pytest.approx(0.1) and coil[-1, 2] == pytest.approx(0.9)       # hooks of 10 % each


def test_helix_tube_is_a_wire_around_the_centerline():
    line = helix.helix_centerline(5, 0.03, 0.08, 16)
    vertices, faces = helix.helix_tube(line, wire_radius=0.004, reference_length=0.4, sides=6)
    np.testing.assert_array_equal(vertices[0], [0, 0, 0])       # start cap centre = start of the helix
    np.testing.assert_array_equal(vertices[-1], [0, 0, 1])      # end cap centre = end of the helix
    assert faces.min() == 0 and faces.max() == len(vertices) - 1
    # in metres (axial coordinate times the reference length), every ring vertex is one wire radius
    # from its centre-line point
    rings = vertices[1:-1].reshape(len(line), 6, 3) * [1, 1, 0.4]
    distance = np.linalg.norm(rings - (line * [1, 1, 0.4])[:, None, :], axis=2)
    np.testing.assert_allclose(distance, 0.004, rtol=1e-9)


def test_spring_rotation_maps_the_axis_onto_the_spring():
    rng = np.random.default_rng(0)
    for _ in range(20):
        direction, side = rng.normal(size=3), rng.normal(size=3)
        rotation = helix.spring_rotation(direction, side)
        np.testing.assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-12)
        assert np.linalg.det(rotation) == pytest.approx(1.0)
        np.testing.assert_allclose(rotation[:, 2], direction / np.linalg.norm(direction), atol=1e-12)
    # a side vector along the spring falls back to another axis instead of failing
    rotation = helix.spring_rotation([0, 0, 2.0], [0, 0, 1.0])
    np.testing.assert_allclose(rotation[:, 2], [0, 0, 1], atol=1e-12)


# ---------------------------------------------------------------------- must hold 3: ends = model ends
def _model_end_points(result, joint_values):
    """World positions of each spring's ends straight from Pinocchio (not from the scene code)."""
    mechanism = result.problem.mechanism
    model = mechanism.model
    data = model.createData()
    ends = {record["name"]: ([], []) for record in result.springs}
    for q in mechanism.configurations(joint_values):
        pin.framesForwardKinematics(model, data, q)
        for record in result.springs:
            for slot, end in enumerate(("a", "b")):
                frame = data.oMf[mechanism.frame_id(record[end]["body"])]
                ends[record["name"]][slot].append(frame.act(np.array(record[end]["point"])))
    return {name: (np.array(a), np.array(b)) for name, (a, b) in ends.items()}


@pytest.mark.parametrize("make", [two_link_design, ur5_design], ids=["two_link", "ur5"])
def test_helix_ends_are_the_model_spring_ends(make):
    result = make()
    rng = np.random.default_rng(5)
    mechanism = result.problem.mechanism
    lower = np.array([j.lower for j in mechanism.joints])
    upper = np.array([j.upper for j in mechanism.joints])
    path = lower + (upper - lower) * rng.random((12, mechanism.nv))
    scene = viz.DesignScene(result, path)
    expected = _model_end_points(result, path)
    lengths = result.evaluate_on(sb.Workspace.from_array(mechanism, path)).lengths   # the CasADi model's lengths
    for column, spring in enumerate(scene.springs):
        starts, ends = expected[spring.name]
        for frame in range(len(path)):
            helix = spring.helix_world(frame)
            np.testing.assert_allclose(helix[0], starts[frame], rtol=0, atol=1e-9)
            np.testing.assert_allclose(helix[-1], ends[frame], rtol=0, atol=1e-9)
            assert np.linalg.norm(helix[-1] - helix[0]) == pytest.approx(lengths[frame, column], abs=1e-9)
            # the coils keep their radius around the axis from end a to end b
            axis = (ends[frame] - starts[frame]) / lengths[frame, column]
            radial = (helix[1:-1] - starts[frame]) - np.outer((helix[1:-1] - starts[frame]) @ axis, axis)
            np.testing.assert_allclose(np.linalg.norm(radial, axis=1), spring.coil_radius, rtol=1e-9)


def _recorded(result, path):
    recorder = SceneRecorder()
    visualizer = meshcat.Visualizer(window=recorder)
    scene = viz.DesignScene(result, path)
    scene.draw(visualizer)
    return scene, recorder


def _quaternion_matrix(x, y, z, w):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def test_what_meshcat_receives_puts_the_helix_ends_on_the_model_ends(design):
    """Decode the commands sent to meshcat (mesh vertices, node transform, animation keys)
    and check the helix ends land on Pinocchio's spring ends in every frame."""
    path = sweeps.animation_path(design, frames_per_joint=8)
    scene, recorder = _recorded(design, path)
    expected = _model_end_points(design, path)
    tree = recorder.tree
    animation = next(umsgpack.unpackb(node.animation) for node in walk(tree) if node.animation is not None)
    clips = {item["path"]: item["clip"] for item in animation["animations"]}
    for spring in scene.springs:
        node = tree["meshcat"][viz.ROOT]["springs"][spring.name]
        obj = umsgpack.unpackb(node.object)["object"]
        geometry = obj["geometries"][0]["data"]["attributes"]["position"]
        vertices = np.frombuffer(geometry["array"].data, dtype=np.float32).reshape(-1, 3)
        first, last = vertices[0].astype(float), vertices[-1].astype(float)
        np.testing.assert_array_equal(first, [0, 0, 0])
        np.testing.assert_array_equal(last, [0, 0, 1])
        # static transform (frame 0): a column-major 4×4 with the stretch in it
        matrix = np.array(umsgpack.unpackb(node.transform)["matrix"]).reshape(4, 4).T
        starts, ends = expected[spring.name]
        np.testing.assert_allclose((matrix @ np.append(first, 1))[:3], starts[0], atol=1e-9)
        np.testing.assert_allclose((matrix @ np.append(last, 1))[:3], ends[0], atol=1e-9)
        # animation: position, quaternion and scale keys of every frame
        clip = clips[f"/meshcat/{viz.ROOT}/springs/{spring.name}"]
        tracks = {track["name"]: [key["value"] for key in track["keys"]] for track in clip["tracks"]}
        assert len(tracks[".position"]) == len(path)
        for frame in range(len(path)):
            rotation = _quaternion_matrix(*tracks[".quaternion"][frame])
            scale = np.array(tracks[".scale"][frame])
            position = np.array(tracks[".position"][frame])
            np.testing.assert_allclose(position + rotation @ (scale * first), starts[frame], atol=1e-9)
            np.testing.assert_allclose(position + rotation @ (scale * last), ends[frame], atol=1e-9)
        colours = next(v for k, v in tracks.items() if k.endswith(".material.color"))
        np.testing.assert_allclose(colours, [scene.color_scale.rgb(t) for t in spring.tensions])


def test_animation_is_replayed_after_the_objects(design):
    """A browser (or the static page) gets the tree depth first; the colour tracks bind to the
    helix meshes only if the animation comes after them."""
    _, recorder = _recorded(design, sweeps.animation_path(design, 8))
    order = [("animation" if node.animation is not None else "object") for node in walk(recorder.tree)
             if node.animation is not None or node.object is not None]
    assert order.count("animation") == 1 and order[-1] == "animation"


# ---------------------------------------------------------------------- colours, regions, paths
def test_colour_scale_is_warm_for_tension_and_green_for_compression():
    scale = colors.ColorScale(200.0)
    assert scale.rgb(0.0) == colors.TENSION_STOPS[0][1]
    assert scale.rgb(200.0) == pytest.approx(colors.TENSION_STOPS[-1][1])
    assert scale.rgb(1e6) == pytest.approx(colors.TENSION_STOPS[-1][1])          # saturates
    assert scale.rgb(-200.0) == pytest.approx(colors.COMPRESSION_STOPS[-1][1])
    brightness = [sum(scale.rgb(t)) for t in np.linspace(0, 200, 11)]
    assert all(b1 > b2 for b1, b2 in zip(brightness, brightness[1:]))        # darker with more tension
    for t in (0.0, 50.0, 150.0):
        r, g, b = scale.rgb(t)
        assert r > g > b                                                        # warm
    r, g, b = scale.rgb(-100.0)
    assert g > r and g > b                                                      # green
    assert scale.css(200.0) == f"#{scale.hex(200.0):06x}" == "#a60026"
    legend = scale.legend_html(compression=True)
    assert "spring tension [N]" in legend and "-200" in legend and "200" in legend


def test_regions_sit_on_their_bodies(design):
    path = sweeps.animation_path(design, 8)
    scene = viz.DesignScene(design, path)
    regions = {(r.spring, r.end): r for r in scene.regions}
    assert set(regions) == {("shoulder", "b"), ("forearm", "a")}                # fixed anchors have none
    segment = regions[("shoulder", "b")]
    assert segment.kind == "segment" and segment.body == "link1"
    np.testing.assert_allclose(segment.corners, [[0.24, 0, 0], [0.38, 0, 0]])  # 0.1 + [0.4, 0.8]·0.35
    box = regions[("forearm", "a")]
    assert box.kind == "box"
    np.testing.assert_allclose(box.corners, [[0.05, 0, 0.03], [0.2, 0, 0.08]])
    kinematics = sb.Workspace.from_array(design.problem.mechanism, path).kinematics().body("link1")
    np.testing.assert_allclose(box.placements[:, :3, 3], kinematics.translation, atol=1e-12)
    np.testing.assert_allclose(box.placements[:, :3, :3], kinematics.rotation, atol=1e-12)
    # each anchor of the design lies in its region
    b_point = np.array(design.spring("shoulder")["b"]["point"])
    assert 0.24 - 1e-12 <= b_point[0] <= 0.38 + 1e-12


def test_animation_path_sweeps_each_joint_and_comes_back(design):
    path = sweeps.animation_path(design, frames_per_joint=16)
    lower, upper = sweeps.workspace_ranges(design)
    np.testing.assert_allclose(path[0], (lower + upper) / 2)
    np.testing.assert_allclose(path[-1], path[0])
    np.testing.assert_allclose(path.min(axis=0), lower)
    np.testing.assert_allclose(path.max(axis=0), upper)
    moving = np.count_nonzero(np.abs(np.diff(path, axis=0)) > 0, axis=1)
    assert np.all(moving == 1)                                   # one joint at a time, no jumps
    assert len(path) == 1 + 2 * 16


def test_mechanism_without_visuals_is_drawn_as_a_stick_figure():
    text = (URDF / "single_link_r2.urdf").read_text()
    text = re.sub(r"<visual>.*?</visual>", "", text, flags=re.S)
    mechanism = sb.Mechanism.from_urdf_string(text, gravity=9.8)
    assert arm.visual_geometry(mechanism).ngeoms == 0
    workspace = sb.Workspace.grid(mechanism, 9)
    spring = sb.ZeroFreeLengthSpring(sb.Anchor("universe", (0, 0, 0.1)), sb.Anchor("link1", (0.2, 0, 0)),
                                     stiffness=122.5)
    result = sb.DesignProblem(mechanism, workspace, [spring]).result(np.zeros(0))
    page = viz.scene_html(result, frames_per_joint=8)
    figure = arm.stick_figure(mechanism.model)
    names = [g.name for g in figure.geometryObjects]
    assert "joint_theta" in names and "com_theta" in names         # a joint ball and the centre of mass
    assert page.count("fetch(\"data:") > 10


def test_urdf_string_with_visuals_uses_them():
    mechanism = sb.Mechanism.from_urdf_string((URDF / "two_link_planar.urdf").read_text())
    geometry = arm.visual_geometry(mechanism)
    assert geometry.ngeoms == 3                                    # link1 box, link2 box, tool sphere
    np.testing.assert_allclose(geometry.geometryObjects[0].meshColor, [*LINK1_RGB, 1.0])


def test_static_page_is_self_contained(design):
    page = viz.scene_html(design, frames_per_joint=8)
    assert page.lstrip().startswith("<!DOCTYPE html>") and "MeshCat.Viewer" in page
    assert 'id="springbalance-legend"' in page
    # nothing is loaded from elsewhere: every command is an inline data: URL, no src/href to a server
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert not re.search(r"fetch\(\s*[\"']https?:", page)
    assert set(re.findall(r"https?://[\w.-]+", page)) <= {"http://www.w3.org"}


# ---------------------------------------------------------------------- must hold 1: real Chromium
def _require_chromium():
    if browser.find_chromium() is None:
        pytest.skip("Chromium is not installed (Debian package `chromium`; `make chromium` installs it as root); "
                    "run `make demo-check` where it is")


def test_scene_renders_in_headless_chromium(design, tmp_path):
    _require_chromium()
    # the report's scene (animation playing): the arm's blue and the springs' colours are on screen
    report = design.report(tmp_path / "out")
    shot = browser.screenshot(report.parent / "scene.html", tmp_path / "scene.png")
    census = browser.colour_census(shot, [LINK1_RGB], browser.scale_colours())
    assert census.ok(), census
    # a still of the first frame: each spring shows the colour of its own tension there
    scene = viz.DesignScene(design, frames_per_joint=8)
    still = tmp_path / "still.html"
    still.write_text(scene.html(autoplay=False))
    shot = browser.screenshot(still, tmp_path / "still.png")
    for spring in scene.springs:
        colour = scene.color_scale.rgb(spring.tensions[0])
        census = browser.colour_census(shot, [LINK1_RGB], [colour])
        assert census.arm >= 150 and census.spring >= 40, (spring.name, colour, census)
    # the stiff shoulder spring is red, the soft forearm spring yellow: hues more than twice the
    # census tolerance apart, so the two counts above are of different pixels
    shoulder, forearm = (360 * colorsys.rgb_to_hsv(*scene.color_scale.rgb(s.tensions[0]))[0] for s in scene.springs)
    assert abs(forearm - shoulder) > 2 * 14


def test_chromium_census_finds_nothing_on_an_empty_scene(tmp_path):
    """Negative control: the page around the scene (background, grid, controls, legend) counts as
    neither arm nor spring. (meshcat's coordinate axes would, in red, green and blue: the scene
    hides them, as here.)"""
    _require_chromium()
    recorder = SceneRecorder()
    visualizer = meshcat.Visualizer(window=recorder)
    visualizer["/Axes"].set_property("visible", False)
    visualizer["/Background"].set_property("top_color", [1.0, 1.0, 1.0])
    visualizer["/Background"].set_property("bottom_color", [0.8, 0.83, 0.88])
    page = tmp_path / "empty.html"
    page.write_text(viz._insert_before_body_end(visualizer.static_html(), colors.ColorScale(100).legend_html(True)))
    census = browser.colour_census(browser.screenshot(page, tmp_path / "empty.png"), [LINK1_RGB],
                                   browser.scale_colours())
    assert census.arm < 5 and census.spring < 5, census


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
            if fields[3] != "0A" or fields[9] not in inodes:     # 0A = LISTEN
                continue
            address, port = fields[1].split(":")
            raw = bytes.fromhex(address)
            if width == 8:
                text = socket.inet_ntop(socket.AF_INET, raw[::-1])
            else:
                text = socket.inet_ntop(socket.AF_INET6, b"".join(raw[i:i + 4][::-1] for i in range(0, 16, 4)))
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
            probe.connect(("192.0.2.1", 9))        # TEST-NET address: nothing is sent
            address = probe.getsockname()[0]
        except OSError:
            return None
    return None if address.startswith("127.") else address


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads listening sockets from /proc")
def test_view_serves_on_loopback_only_and_stops_cleanly_on_ctrl_c(design_file):
    port = _free_port()
    process = subprocess.Popen([sys.executable, "-m", "springbalance.cli", "view", str(design_file), "--port", str(port),
                                "--frames", "8"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        first = process.stdout.readline()
        assert f"http://127.0.0.1:{port}/static/" in first, (first, process.stderr.read() if process.poll() else "")
        servers = _children(process.pid)
        assert len(servers) == 1
        sockets = _listening_sockets(servers[0]) + _listening_sockets(process.pid)
        assert (("127.0.0.1", port) in sockets) and len(sockets) >= 2, sockets    # web page and ZeroMQ
        assert all(address == "127.0.0.1" for address, _ in sockets), sockets
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/static/", timeout=10) as response:
            assert response.status == 200 and b"meshcat" in response.read().lower()
        outside = _outside_address()
        if outside is not None:
            with pytest.raises(OSError):
                socket.create_connection((outside, port), timeout=2).close()
        time.sleep(0.3)
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert process.returncode in (0, 130), (process.returncode, err)
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


def test_view_on_a_busy_port_fails_in_one_line(design_file):
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        completed = subprocess.run([sys.executable, "-m", "springbalance.cli", "view", str(design_file), "--port",
                                    str(port)], capture_output=True, text=True, timeout=60)
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


# ---------------------------------------------------------------------- springs that fit the arm
# urdf/two_link_planar_collision.urdf (see its header): both joints turn about (0, -1, 0), so a
# positive angle lifts a link from +x towards +z; link1 runs 0.5 m along x from the shoulder (the
# origin), link2's collision box is 0.4 × 0.03 × 0.03 m, centred 0.2 m along link2 from the elbow.
# "crossing" runs from the ground point P = (0.6, 0, 0.25) to S = (0.4, 0, 0) on link1; with the
# shoulder at 0 the elbow sits at E = (0.5, 0, 0) and link2 points along (cos e, 0, sin e).
COLLISION_URDF = URDF / "two_link_planar_collision.urdf"
CROSSING_P, CROSSING_S, ELBOW = np.array([0.6, 0.0, 0.25]), np.array([0.4, 0.0, 0.0]), np.array([0.5, 0.0, 0.0])
LINK2_LENGTH, LINK2_HALF_WIDTH = 0.4, 0.015                 # [m] of link2's box
CAPSULE_RADIUS = 0.01                                      # [m] of a spring without a spec sheet
MARGIN = 0.02                                              # [m]


def _fixed_design(urdf, springs, path, **options):
    """A design of fixed springs (no free variable) whose workspace is ``path`` (N×2) [rad]."""
    mechanism = sb.Mechanism.from_urdf(urdf)
    problem = sb.DesignProblem(mechanism, sb.Workspace.from_array(mechanism, path), springs, **options)
    return problem.result(np.zeros(0))


def _crossing_spring():
    return sb.ExtensionSpring(sb.Anchor("universe", tuple(CROSSING_P)), sb.Anchor("link1", tuple(CROSSING_S)),
                              name="crossing", stiffness=300.0, free_length=0.05)


def _elbow_path(degrees):
    elbow = np.radians(degrees)
    return np.column_stack([np.zeros_like(elbow), elbow])


def _crosses_link2_axis(elbow: float) -> bool:
    """Does the spring's segment S–P cross link2's centre line E + t (cos e, 0, sin e), 0 ≤ t ≤ 0.4?
    Where it does, the capsule around the spring holds a point inside link2's box: an overlap."""
    axis = np.array([np.cos(elbow), np.sin(elbow)])                       # in the x–z plane
    spring = (CROSSING_P - CROSSING_S)[[0, 2]]
    u, t = np.linalg.solve(np.column_stack([spring, -axis]), (ELBOW - CROSSING_S)[[0, 2]])
    return 0 <= u <= 1 and 0 <= t <= LINK2_LENGTH


def _hue_distance(rgb_1, rgb_2) -> float:
    h1, h2 = (360 * colorsys.rgb_to_hsv(*rgb)[0] for rgb in (rgb_1, rgb_2))
    return abs((h1 - h2 + 180) % 360 - 180)


def _clips(recorder):
    animation = next(umsgpack.unpackb(node.animation) for node in walk(recorder.tree) if node.animation is not None)
    return {item["path"]: {track["name"]: [key["value"] for key in track["keys"]] for track in item["clip"]["tracks"]}
            for item in animation["animations"]}


def _draw(scene):
    recorder = SceneRecorder()
    scene.draw(meshcat.Visualizer(window=recorder))
    return recorder


def test_clearance_colour_is_not_on_the_tension_scale():
    """The clearance colour must not read as a tension (or compression) or as the arm: its hue is more
    than twice the census tolerance (14°) from every colour of the scale and from link1's blue."""
    for colour in browser.scale_colours(401) + [LINK1_RGB]:
        assert _hue_distance(colors.CLEARANCE_RGB, colour) > 2 * 14, colour
    r, g, b = colors.CLEARANCE_RGB
    assert colorsys.rgb_to_hsv(r, g, b)[1] > 0.9                           # a saturated colour, not grey
    assert f"#{colors.CLEARANCE_COLOR:06x}" in colors.ColorScale(10).legend_html(clearance_margin=0.012)


def test_spring_is_magenta_where_it_passes_through_link2():
    degrees = [-90, -45, 0, 75, 90, 120, 150]
    path = _elbow_path(degrees)
    crossing = [_crosses_link2_axis(e) for e in path[:, 1]]
    assert crossing == [False, False, False, True, True, True, True]       # the geometry above, worked out
    result = _fixed_design(COLLISION_URDF, [_crossing_spring()], path)
    scene = viz.DesignScene(result, path, margin=MARGIN)
    track = scene.springs[0]
    assert track.radius == CAPSULE_RADIUS
    # where link2's centre line crosses the spring, the capsule overlaps link2's box
    assert np.all(track.clearance[3:] < 0) and np.all(track.below_margin[3:])
    # elbow at -90°: link2 hangs down from E, so its box spans x ∈ [0.485, 0.515], z ∈ [-0.4, 0]; the box's
    # corner (0.485, ·, 0) is the point closest to the line S–P (whose foot lies within the segment), at
    # |(0.485 - 0.4)·0.25 - 0·0.2| / |(0.2, 0.25)| from it. link1 (the spring's anchor body) is exempt,
    # though S lies inside its box.
    direction = (CROSSING_P - CROSSING_S)[[0, 2]]
    corner = np.array([ELBOW[0] - LINK2_HALF_WIDTH, 0.0]) - CROSSING_S[[0, 2]]
    foot = corner @ direction / (direction @ direction)
    assert 0 < foot < 1
    expected = abs(corner[0] * direction[1] - corner[1] * direction[0]) / np.linalg.norm(direction) - CAPSULE_RADIUS
    assert track.clearance[0] == pytest.approx(expected, abs=1e-6)
    assert expected > MARGIN and not track.below_margin[0]
    # what meshcat receives: the colour track is magenta in the crossing frames, the tension colour elsewhere
    recorder = _draw(scene)
    helix = umsgpack.unpackb(recorder.tree["meshcat"][viz.ROOT]["springs"]["crossing"].object)["object"]
    assert helix["materials"][0]["color"] == scene.color_scale.hex(track.tensions[0])      # frame 0 is clear
    clip = _clips(recorder)[f"/meshcat/{viz.ROOT}/springs/crossing"]
    colours = next(values for name, values in clip.items() if name.endswith(".material.color"))
    for frame, crosses in enumerate(crossing):
        if crosses:
            np.testing.assert_allclose(colours[frame], colors.CLEARANCE_RGB)
        else:
            np.testing.assert_allclose(colours[frame], scene.color_scale.rgb(track.tensions[frame]))
            assert _hue_distance(colours[frame], colors.CLEARANCE_RGB) > 28
    legend = scene.legend_html()
    assert "below clearance margin (20 mm)" in legend and "magenta" in legend
    assert "below clearance margin (20 mm)" in scene.html(animate=False)


def test_clearance_distances_are_those_of_the_clearance_check():
    """Same rule as springbalance.results.clearance: over the same poses, the smallest distance agrees."""
    path = _elbow_path(np.linspace(-90, 60, 11))
    result = _fixed_design(COLLISION_URDF, [_crossing_spring()], path)
    scene = viz.DesignScene(result, path, margin=MARGIN)
    row = result.clearance(margin=MARGIN).row("crossing")
    assert np.min(scene.springs[0].clearance) == pytest.approx(row.distance, abs=1e-9)
    assert int(np.argmin(scene.springs[0].clearance)) == row.sample


def test_margin_defaults_to_the_problems_clearance():
    path = _elbow_path([-90, 120])
    design = _fixed_design(COLLISION_URDF, [_crossing_spring()], path, clearance=sb.Clearance(margin=MARGIN))
    scene = viz.DesignScene(design, path)
    assert scene.margin == MARGIN
    np.testing.assert_array_equal(scene.springs[0].below_margin, [False, True])
    # without a clearance in the problem and without a margin, nothing is checked
    plain = viz.DesignScene(_fixed_design(COLLISION_URDF, [_crossing_spring()], path), path)
    assert plain.margin is None and plain.springs[0].clearance is None
    assert "clearance" not in plain.legend_html()
    with pytest.raises(sb.InputError, match="margin"):
        viz.DesignScene(design, path, margin=-0.01)


def test_without_collision_geometry_the_scene_is_drawn_by_tension():
    path = _elbow_path([-90, 120])                                       # 120°: crosses link2 on the other URDF
    result = _fixed_design(URDF / "two_link_planar.urdf", [_crossing_spring()], path)
    scene = viz.DesignScene(result, path, margin=MARGIN)
    track = scene.springs[0]
    assert track.clearance is None and track.below_margin is None
    assert "no collision geometry" in scene.clearance_note
    clip = _clips(_draw(scene))[f"/meshcat/{viz.ROOT}/springs/crossing"]
    colours = next(values for name, values in clip.items() if name.endswith(".material.color"))
    np.testing.assert_allclose(colours, [scene.color_scale.rgb(t) for t in track.tensions])
    assert "clearance" not in scene.legend_html()


def test_no_clearance_entry_when_every_frame_is_clear():
    path = _elbow_path([-90, -45, 0])
    scene = viz.DesignScene(_fixed_design(COLLISION_URDF, [_crossing_spring()], path), path, margin=MARGIN)
    assert np.all(scene.springs[0].clearance > MARGIN)
    assert not scene.clearance_violated and "clearance" not in scene.legend_html()


def _label_texts(page: str) -> dict[str, str]:
    """Text of every ``_text`` texture in a static page (its commands are inline base64 msgpack), by the
    path of the node that holds it."""
    import base64

    texts = {}
    for data in re.findall(r'fetch\("data:application/octet-binary;base64,([A-Za-z0-9+/=]+)"\)', page):
        command = umsgpack.unpackb(base64.b64decode(data))
        if command.get("type") == "set_object":
            for texture in command["object"].get("textures", []):
                if texture.get("type") == "_text":
                    texts[command["path"]] = texture["text"]
    return texts


def test_each_spring_carries_its_name_near_its_middle(design):
    path = sweeps.animation_path(design, frames_per_joint=8)
    scene = viz.DesignScene(design, path)
    names = [spring.name for spring in scene.springs]
    assert names == ["shoulder", "forearm"]
    recorder = _draw(scene)
    clips = _clips(recorder)
    ends = _model_end_points(design, path)
    for spring in scene.springs:
        node = recorder.tree["meshcat"][viz.ROOT]["labels"][spring.name]
        obj = umsgpack.unpackb(node.object)["object"]
        assert obj["object"]["type"] == "Sprite"                             # always faces the camera
        (texture,) = obj["textures"]
        assert texture["type"] == "_text" and texture["text"] == spring.name
        assert obj["materials"][0]["map"] == texture["uuid"]
        # the label follows the spring: in every frame it sits a fixed small height above the middle of the
        # spring's ends (from Pinocchio)
        middle = (ends[spring.name][0] + ends[spring.name][1]) / 2
        positions = np.array(clips[f"/meshcat/{viz.ROOT}/labels/{spring.name}"][".position"])
        assert positions.shape == middle.shape == (len(path), 3)
        np.testing.assert_allclose(positions[:, :2], middle[:, :2], atol=1e-12)
        lift = positions[:, 2] - middle[:, 2]
        np.testing.assert_allclose(lift, lift[0], atol=1e-12)
        assert 0 < lift[0] < 0.05
    # and the static page holds the labels' text
    texts = _label_texts(scene.html())
    assert {path.rsplit("/", 1)[-1]: text for path, text in texts.items()} == {name: name for name in names}


def _camera(recorder):
    """World position [m] of meshcat's camera from the recorded commands (it looks at the world origin,
    the target of meshcat's orbit controls, from its ``/Cameras/default/rotated`` node)."""
    transform = recorder.tree["Cameras"]["default"].transform
    if transform is not None:
        np.testing.assert_allclose(np.array(umsgpack.unpackb(transform)["matrix"]).reshape(4, 4), np.eye(4))
    properties = [umsgpack.unpackb(p) for p in recorder.tree["Cameras"]["default"]["rotated"]["<object>"].properties]
    x, y_up, minus_y = next(p["value"] for p in properties if p["property"] == "position")
    return np.array([x, -minus_y, y_up])          # the rotated node turns meshcat's y-up frame back to z-up


@pytest.mark.parametrize("make", [two_link_design, lambda: _fixed_design(
    COLLISION_URDF, [_crossing_spring()], _elbow_path(np.linspace(-150, 150, 13)))], ids=["two_link", "crossing"])
def test_camera_sees_every_spring_end_and_link_in_every_frame(make):
    result = make()
    path = sweeps.animation_path(result, frames_per_joint=12)
    scene = viz.DesignScene(result, path)
    camera = _camera(_draw(scene))
    ends = _model_end_points(result, path)
    mechanism = result.problem.mechanism
    model, data = mechanism.model, mechanism.model.createData()
    links = []
    for q in mechanism.configurations(path):
        pin.framesForwardKinematics(model, data, q)
        links += [data.oMf[f].translation.copy() for f in range(model.nframes)]      # joints, link ends, tool
    points = np.vstack([np.vstack(pair) for pair in ends.values()] + [np.array(links)])
    # within the bounding sphere, and within meshcat's field of view (75° vertical) around the line of sight
    assert np.all(np.linalg.norm(points - scene.camera_center, axis=1) <= scene.camera_radius + 1e-12)
    sight = -camera / np.linalg.norm(camera)
    rays = points - camera
    angles = np.degrees(np.arccos(rays @ sight / np.linalg.norm(rays, axis=1)))
    assert angles.max() <= 75 / 2, angles.max()
    assert angles.max() > 0.5 * 75 / 2             # and the camera is not so far that the arm is a speck


def test_legend_pushing_part_only_for_a_spring_that_pushes():
    """A compression spring from (0, 0, -0.3) to (0.2, 0, 0) on link1 is L = sqrt(0.13 + 0.12 sin s) long
    (shoulder s, elbow free); with l0 = 0.3 m its tension k (L - l0) is negative (it pushes) for
    sin s < -1/3 only. The design's workspace covers both, the legend follows the animation's frames."""
    spring = sb.CompressionSpring(sb.Anchor("universe", (0.0, 0.0, -0.3)), sb.Anchor("link1", (0.2, 0.0, 0.0)),
                                  name="strut", stiffness=200.0, free_length=0.3)
    shoulder = np.radians(np.linspace(-90, 90, 13))
    result = _fixed_design(URDF / "two_link_planar.urdf", [spring], np.column_stack([shoulder, np.zeros(13)]))
    pushing_in_design = 200.0 * (np.sqrt(0.13 + 0.12 * np.sin(shoulder)) - 0.3)
    assert np.any(pushing_in_design < -1) and np.any(pushing_in_design > 1)

    def scene_over(degrees):
        angles = np.radians(degrees)
        scene = viz.DesignScene(result, np.column_stack([angles, np.zeros_like(angles)]))
        np.testing.assert_allclose(scene.springs[0].tensions, 200.0 * (np.sqrt(0.13 + 0.12 * np.sin(angles)) - 0.3),
                                   rtol=1e-9)
        return scene

    lifting = scene_over(np.linspace(0, 90, 7))             # L ≥ sqrt(0.13) > 0.3: never pushes
    assert not lifting.compression
    assert "pushing" not in lifting.legend_html() and "pushing" not in lifting.html(animate=False)
    assert not re.search(r">-\d", lifting.legend_html())     # no negative tick
    lowering = scene_over(np.linspace(-90, 0, 7))           # pushes below s = -19.5°
    assert lowering.compression
    assert "(negative: pushing)" in lowering.legend_html() and re.search(r">-\d", lowering.legend_html())


def test_magenta_spring_renders_in_headless_chromium(tmp_path):
    _require_chromium()
    path = _elbow_path([120])                                 # link2 passes through the spring
    scene = viz.DesignScene(_fixed_design(COLLISION_URDF, [_crossing_spring()], path), path, margin=MARGIN)
    page = tmp_path / "clearance.html"
    page.write_text(scene.html(autoplay=False))
    census = browser.colour_census(browser.screenshot(page, tmp_path / "clearance.png"), [LINK1_RGB],
                                   [colors.CLEARANCE_RGB])
    assert census.arm >= 150 and census.spring >= 40, census
