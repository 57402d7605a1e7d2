"""`xrdf viz`: scene, rerun (.rrd read back), MCAP (read back and decoded), PNG, CLI.

Real inputs: the example-robot-data Panda URDF with fixtures/panda/panda.xrdf (61 spheres).
The sampled scene (seed 0) contains self-colliding configurations, so colouring is checked on
real contacts.
"""

from __future__ import annotations

import json
import subprocess
import sys
from collections import Counter, defaultdict
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES
from tests.robots import dollar_robot, panda_copy_with_mesh, robot_urdf
from xrdf_tools.cli import app
from xrdf_tools.robot.kinematics import build_kinematic_model
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.selfcollision.collision import colliding_frame_pairs
from xrdf_tools.util.errors import GeometryGroupError, SourceError
from xrdf_tools.viz import (
    COLLISION_RGBA,
    Scene,
    build_scene,
    choose_group,
    load_configurations,
    render,
    sample_configurations,
    sphere_counts,
)
from xrdf_tools.xrdf.io import load_xrdf
from xrdf_tools.xrdf.model import Xrdf

PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"
N_SAMPLES = 40
RED8 = [round(255 * v) for v in COLLISION_RGBA]


# ------------------------------------------------------------------------------------------
# Fixtures
# ------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def panda_urdf() -> Path:
    return robot_urdf("panda")


@pytest.fixture(scope="module")
def panda(panda_urdf: Path) -> tuple[Any, Xrdf]:
    return load_urdf(panda_urdf), load_xrdf(PANDA_XRDF)


@pytest.fixture(scope="module")
def scene(panda: tuple[Any, Xrdf], panda_urdf: Path) -> Scene:
    urdf, xrdf = panda
    kin, _ = build_kinematic_model(urdf, xrdf)
    Q = sample_configurations(kin, xrdf, N_SAMPLES, seed=0)
    return build_scene(urdf, xrdf, Q, kinematic_model=kin, meshes="collision", urdf_path=panda_urdf)


@pytest.fixture(scope="module")
def xrdf_counts(panda: tuple[Any, Xrdf]) -> dict[str, int]:
    xrdf = panda[1]
    return {f: len(s) for f, s in xrdf.resolved_spheres("panda_spheres").items()}


# ------------------------------------------------------------------------------------------
# Scene
# ------------------------------------------------------------------------------------------
def test_scene_has_every_xrdf_sphere_with_its_true_radius(
    scene: Scene, panda: tuple[Any, Xrdf], xrdf_counts: dict[str, int]
) -> None:
    xrdf = panda[1]
    assert scene.group == "panda_spheres"
    assert sum(xrdf_counts.values()) == 61 == scene.n_spheres
    drawn = {k: v for k, v in scene.sphere_counts().items() if v}
    assert drawn == xrdf_counts == sphere_counts(xrdf, "panda_spheres")
    for frame, spheres in xrdf.resolved_spheres("panda_spheres").items():
        link = scene.link(frame)
        np.testing.assert_array_equal(link.radii, [s.radius for s in spheres])
        np.testing.assert_array_equal(link.centers, [s.center for s in spheres])
        buf = xrdf.self_collision.buffer_distance.get(frame, 0.0)  # type: ignore[union-attr]
        np.testing.assert_allclose(link.buffered_radii, link.radii + buf)


def test_links_have_distinct_colours_and_none_is_collision_red(scene: Scene) -> None:
    colours = [link.color for link in scene.links if link.n_spheres]
    assert len(set(colours)) == len(colours) == 11
    assert COLLISION_RGBA not in colours


def test_timeline_starts_at_the_default_pose(scene: Scene, panda: tuple[Any, Xrdf]) -> None:
    urdf, xrdf = panda
    kin, _ = build_kinematic_model(urdf, xrdf)
    assert len(scene.samples) == N_SAMPLES + 1
    assert scene.poses.shape == (N_SAMPLES + 1, kin.n_frames, 4, 4)
    first = scene.samples[0]
    assert first.source == -1 and first.label == "default pose"
    j4 = kin.actuated_index("panda_joint4")
    assert first.q[j4] == pytest.approx(-2.5)
    assert [s.source for s in scene.samples[1:]] == list(range(N_SAMPLES))


def test_contacts_and_red_spheres_follow_the_collision_module(
    scene: Scene, panda: tuple[Any, Xrdf]
) -> None:
    urdf, xrdf = panda
    kin, _ = build_kinematic_model(urdf, xrdf)
    hits = 0
    for step, sample in enumerate(scene.samples):
        expected = {(c.frame_a, c.frame_b) for c in colliding_frame_pairs(kin, xrdf, sample.q)}
        assert set(sample.colliding_pairs()) == expected
        colours = scene.colors(step)
        red = {(name, i) for name, cs in colours.items() for i, c in enumerate(cs) if c == RED}
        want = {(f, i) for f, ids in sample.colliding_spheres().items() for i in ids}
        assert red == want
        assert all(p.clearance < 0 for p in sample.contacts)
        hits += bool(sample.contacts)
    assert hits >= 2  # seed 0 gives real self-collisions to look at
    assert not scene.samples[0].contacts  # the default pose is collision-free


RED = COLLISION_RGBA


def test_colliding_only_keeps_the_default_pose_and_colliding_samples(
    scene: Scene, panda: tuple[Any, Xrdf], panda_urdf: Path
) -> None:
    urdf, xrdf = panda
    Q = np.array([s.q for s in scene.samples[1:]])
    only = build_scene(urdf, xrdf, Q, meshes="none", colliding_only=True, urdf_path=panda_urdf)
    colliding = [s.source for s in scene.samples[1:] if s.contacts]
    assert [s.source for s in only.samples] == [-1, *colliding]
    assert all(s.contacts for s in only.samples[1:])
    assert all(not link.meshes for link in only.links)


def test_group_choice(panda: tuple[Any, Xrdf]) -> None:
    xrdf = panda[1]
    assert choose_group(xrdf) == "panda_spheres"
    with pytest.raises(GeometryGroupError, match="did you mean 'panda_spheres'"):
        choose_group(xrdf, "panda_sphere")


def test_collision_meshes_are_loaded_in_the_link_frame(scene: Scene) -> None:
    link0 = scene.link("panda_link0")
    assert link0.meshes and all(m.n_triangles > 0 for m in link0.meshes)
    v = np.vstack([m.vertices for m in link0.meshes])
    # the base casting sits on the floor, inside a 0.4 m box around the link origin
    assert v[:, 2].min() == pytest.approx(0.0, abs=0.01)
    assert np.abs(v).max() < 0.4


def test_unresolvable_meshes_are_warnings_and_package_path_fixes_them(
    panda: tuple[Any, Xrdf], panda_urdf: Path, tmp_path: Path
) -> None:
    xrdf = panda[1]
    moved = tmp_path / "panda.urdf"  # away from its package: package:// URIs cannot resolve
    moved.write_bytes(panda_urdf.read_bytes())
    urdf = load_urdf(moved)
    lost = build_scene(urdf, xrdf, meshes="collision", urdf_path=moved)
    warned = {d.message.split("'")[1] for d in lost.diagnostics if d.rule == "mesh-not-loaded"}
    fingers = {"panda_leftfinger", "panda_rightfinger"}  # collision boxes: need no file
    assert warned == {link.name for link in lost.links} - fingers
    assert "--package-path example-robot-data=DIR" in lost.diagnostics[0].message
    assert {link.name for link in lost.links if link.meshes} == fingers
    assert lost.n_spheres == 61
    share = panda_urdf.parents[3]  # .../share/example-robot-data
    found = build_scene(
        urdf,
        xrdf,
        meshes="collision",
        urdf_path=moved,
        package_paths={"example-robot-data": str(share)},
    )
    assert not [d for d in found.diagnostics if d.rule == "mesh-not-loaded"]
    assert all(link.meshes for link in found.links)


def test_another_group_is_drawn_without_collision_colours(
    panda: tuple[Any, Xrdf], panda_urdf: Path
) -> None:
    from xrdf_tools.util.frozen import FrozenMap
    from xrdf_tools.xrdf.model import GeometryGroup, Sphere

    urdf, xrdf = panda
    coarse = GeometryGroup(FrozenMap({"panda_hand": (Sphere((0.0, 0.0, 0.05), 0.1),)}))
    assert xrdf.geometry is not None
    two = xrdf.replace(geometry=FrozenMap({**xrdf.geometry, "coarse": coarse}))
    # folded onto itself: the self-collision group collides
    q = np.zeros((1, 8))
    kin, _ = build_kinematic_model(urdf, two)
    q[0, kin.actuated_index("panda_joint2")] = 1.7
    q[0, kin.actuated_index("panda_joint4")] = -3.0
    s = build_scene(urdf, two, q, group="coarse", meshes="none", urdf_path=panda_urdf)
    assert s.sphere_counts() == {"panda_hand": 1}
    assert s.samples[1].contacts and not s.collisions_shown
    assert all(c != RED for cs in s.colors(1).values() for c in cs)
    assert [d.rule for d in s.diagnostics] == ["viz-collisions-not-drawn"]


def test_a_small_negative_radius_is_drawn_like_the_check_sees_it_and_a_slot_is_not(
    panda: tuple[Any, Xrdf], tmp_path: Path
) -> None:
    """XRDF 1.0: a sphere of radius -0.01 is a real sphere once buffered (the self-collision
    check uses it), so it is drawn and turns red when it collides; an attached-object slot
    (radius -10) is neither checked nor drawn."""
    urdf, base = panda
    kin, _ = build_kinematic_model(urdf, base)
    plain = build_scene(urdf, base, None, kinematic_model=kin, meshes="none")
    link0, link3 = (plain.frame_names.index(f) for f in ("panda_link0", "panda_link3"))
    world = plain.poses[0, link3] @ np.append(
        base.resolved_spheres("panda_spheres")["panda_link3"][0].center, 1.0
    )
    at = (np.linalg.inv(plain.poses[0, link0]) @ world)[:3].tolist()
    text = PANDA_XRDF.read_text().replace("format_version: 2.0", "format_version: 1.0")
    text = text.replace("world_collision:", "collision:").replace(
        "      panda_link0:\n",
        "      panda_link0:\n"
        f"        - center: [{at[0]!r}, {at[1]!r}, {at[2]!r}]\n          radius: -0.01\n"
        "        - center: [0.0, 0.0, 0.0]\n          radius: -10.0\n",
        1,
    )
    path = tmp_path / "panda_1_0.xrdf"
    path.write_text(text)
    xrdf = load_xrdf(path)
    scene = build_scene(urdf, xrdf, None, meshes="none")
    drawn = scene.link("panda_link0")
    assert drawn.sphere_ids == (0, 2, 3)  # the slot (index 1) is left out
    assert drawn.radii[0] == 0.0 and drawn.buffered_radii[0] == pytest.approx(0.09)
    assert ("panda_link0", "panda_link3") in scene.samples[0].colliding_pairs()
    assert scene.colors(0)["panda_link0"][0] == COLLISION_RGBA
    notes = [d.message for d in scene.diagnostics if d.rule == "viz-placeholder-spheres"]
    assert notes == ["1 attached-object slot(s) (radius <= -1) in group 'panda_spheres' not drawn"]
    assert sphere_counts(xrdf, "panda_spheres")["panda_link0"] == 3


# ------------------------------------------------------------------------------------------
# rerun
# ------------------------------------------------------------------------------------------
def _rrd_columns(path: Path) -> dict[tuple[str, bool], dict[str, list[Any]]]:
    from rerun.chunk import RrdReader

    out: dict[tuple[str, bool], dict[str, list[Any]]] = defaultdict(lambda: defaultdict(list))
    for chunk in RrdReader(path).stream():
        rb = chunk.to_record_batch()
        for name in rb.schema.names:
            if ":" not in name and name != "sample":
                continue  # row ids, log_time
            out[(chunk.entity_path, chunk.is_static)][name].extend(rb.column(name).to_pylist())
    return out


def test_rrd_is_written_and_reads_back(
    scene: Scene, tmp_path: Path, xrdf_counts: dict[str, int]
) -> None:
    pytest.importorskip("rerun")
    out = tmp_path / "panda.rrd"
    render(scene, "rrd", out, buffered=True)
    assert [p.name for p in tmp_path.iterdir()] == ["panda.rrd"]  # no temporary left over
    cols = _rrd_columns(out)
    n_steps = len(scene.samples)
    for frame, n in xrdf_counts.items():
        static = cols[(f"/robot/{frame}/spheres", True)]
        (centers,) = static["Ellipsoids3D:centers"]
        (half,) = static["Ellipsoids3D:half_sizes"]
        assert len(centers) == len(half) == n
        np.testing.assert_allclose(np.array(half)[:, 0], scene.link(frame).radii, rtol=1e-6)
        (buffered,) = cols[(f"/robot/{frame}/buffered", True)]["Ellipsoids3D:half_sizes"]
        np.testing.assert_allclose(
            np.array(buffered)[:, 0], scene.link(frame).buffered_radii, rtol=1e-6
        )
        tf = cols[(f"/robot/{frame}", False)]
        assert sorted(tf["sample"]) == list(range(n_steps))
        assert cols[(f"/robot/{frame}/mesh/0", True)]["Mesh3D:vertex_positions"]
    # the last pose of the hand is the FK pose of the last sample
    tf = cols[("/robot/panda_hand", False)]
    last = int(np.argmax(tf["sample"]))
    hand = scene.frame_names.index("panda_hand")
    np.testing.assert_allclose(
        tf["Transform3D:translation"][last][0], scene.poses[-1, hand, :3, 3], atol=1e-6
    )
    # red spheres at every step with a collision; pairs named in the text log
    colour_steps = {
        step
        for (ent, static), c in cols.items()
        if ent.endswith("/spheres") and not static
        for step, colours in zip(c["sample"], c["Ellipsoids3D:colors"], strict=True)
        if any(_rgba8(x) == RED8 for x in colours)
    }
    colliding = {k for k, s in enumerate(scene.samples) if s.contacts}
    assert colour_steps == colliding
    log = cols[("/collisions", False)]
    assert len(log["TextLog:text"]) == sum(len(s.frame_contacts) for s in scene.samples)
    assert set(log["sample"]) == colliding
    first = min(colliding)
    a, b = scene.samples[first].colliding_pairs()[0]
    texts = [t[0] for t, s in zip(log["TextLog:text"], log["sample"], strict=True) if s == first]
    assert any(a in t and b in t and "clearance" in t for t in texts)
    assert {lv[0] for lv in log["TextLog:level"]} == {"WARN"}
    assert len(cols[("/samples", False)]["TextLog:text"]) == n_steps


def test_rrd_passes_rerun_rrd_verify(scene: Scene, tmp_path: Path) -> None:
    pytest.importorskip("rerun_cli")
    out = tmp_path / "panda.rrd"
    render(scene, "rrd", out)
    home = tmp_path / "home"  # a fresh config: the CLI's first run never sends usage data
    env = {"HOME": str(home), "XDG_CONFIG_HOME": str(home), "XDG_DATA_HOME": str(home)}
    cli = "import sys; from rerun_cli.__main__ import main; sys.exit(main())"
    run = [sys.executable, "-c", cli, "rrd", "verify"]
    ok = subprocess.run([*run, str(out)], capture_output=True, text=True, env=env, timeout=60)
    assert ok.returncode == 0, ok.stderr
    truncated = tmp_path / "truncated.rrd"
    truncated.write_bytes(out.read_bytes()[: out.stat().st_size // 2])
    bad = subprocess.run([*run, str(truncated)], capture_output=True, text=True, env=env)
    assert bad.returncode != 0


def test_spawn_streams_the_same_recording(
    scene: Scene, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    rr = pytest.importorskip("rerun")
    sink = tmp_path / "spawned.rrd"

    def fake_spawn(self: Any, **_: Any) -> None:  # no viewer in tests: divert to a file
        self.save(str(sink))

    monkeypatch.setattr(rr.RecordingStream, "spawn", fake_spawn)
    render(scene, "spawn")
    cols = _rrd_columns(sink)
    assert sorted(cols[("/robot/panda_hand", False)]["sample"]) == list(range(len(scene.samples)))


def _rgba8(packed: int) -> list[int]:
    """rerun stores colours as one 0xRRGGBBAA integer."""
    return [(packed >> 24) & 255, (packed >> 16) & 255, (packed >> 8) & 255, packed & 255]


# ------------------------------------------------------------------------------------------
# MCAP
# ------------------------------------------------------------------------------------------
def _read_mcap(path: Path) -> tuple[dict[str, Any], list[tuple[str, int, Any]]]:
    from mcap.reader import make_reader

    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        assert summary is not None
        channels = {
            c.topic: (c.message_encoding, summary.schemas[c.schema_id])
            for c in summary.channels.values()
        }
        messages = [
            (channel.topic, message.log_time, json.loads(message.data))
            for _schema, channel, message in reader.iter_messages(log_time_order=False)
        ]
    return channels, messages


def test_mcap_is_foxglove_json_and_reads_back(
    scene: Scene, tmp_path: Path, xrdf_counts: dict[str, int]
) -> None:
    pytest.importorskip("mcap")
    out = tmp_path / "panda.mcap"
    render(scene, "mcap", out, buffered=True)
    channels, messages = _read_mcap(out)
    assert {t: (enc, s.name, s.encoding) for t, (enc, s) in channels.items()} == {
        "/tf": ("json", "foxglove.FrameTransform", "jsonschema"),
        "/xrdf/spheres": ("json", "foxglove.SceneUpdate", "jsonschema"),
        "/xrdf/buffered": ("json", "foxglove.SceneUpdate", "jsonschema"),
        "/xrdf/meshes": ("json", "foxglove.SceneUpdate", "jsonschema"),
        "/xrdf/collisions": ("json", "foxglove.Log", "jsonschema"),
    }
    n_steps = len(scene.samples)
    n_frames = len(scene.frame_names)
    counts = Counter(topic for topic, _, _ in messages)
    assert counts == {
        "/tf": n_steps * (n_frames - 1),
        "/xrdf/spheres": n_steps,
        "/xrdf/collisions": n_steps,
        "/xrdf/buffered": 1,
        "/xrdf/meshes": 1,
    }
    spheres = [(t, m) for topic, t, m in messages if topic == "/xrdf/spheres"]
    times = [t for t, _ in spheres]
    assert times == sorted(set(times))  # strictly increasing: one message per sample
    for step, (_, update) in enumerate(spheres):
        by_link = {e["frame_id"]: e for e in update["entities"]}
        assert {f: len(e["spheres"]) for f, e in by_link.items()} == xrdf_counts
        hit = scene.samples[step].colliding_spheres()
        for frame, entity in by_link.items():
            link = scene.link(frame)
            sizes = [s["size"] for s in entity["spheres"]]
            np.testing.assert_allclose([s["x"] for s in sizes], 2 * link.radii)
            assert all(s["x"] == s["y"] == s["z"] for s in sizes)
            red = {
                i
                for i, s in enumerate(entity["spheres"])
                if tuple(s["color"].values()) == COLLISION_RGBA
            }
            assert red == hit.get(frame, set())
    (buffered,) = [m for topic, _, m in messages if topic == "/xrdf/buffered"]
    for e in buffered["entities"]:
        link = scene.link(e["frame_id"])
        np.testing.assert_allclose([s["size"]["x"] for s in e["spheres"]], 2 * link.buffered_radii)
    (meshes,) = [m for topic, _, m in messages if topic == "/xrdf/meshes"]
    for e in meshes["entities"]:
        for tri in e["triangles"]:
            idx = tri["indices"]
            assert idx and len(idx) % 3 == 0 and max(idx) < len(tri["points"])
    logs = [m for topic, _, m in messages if topic == "/xrdf/collisions"]
    for sample, log in zip(scene.samples, logs, strict=True):
        for a, b in sample.colliding_pairs():
            assert a in log["message"] and b in log["message"]
        assert log["level"] == (3 if sample.contacts else 2)


def test_mcap_transforms_rebuild_the_fk_poses(scene: Scene, tmp_path: Path) -> None:
    pytest.importorskip("mcap")
    out = tmp_path / "panda.mcap"
    render(scene, "mcap", out)
    _, messages = _read_mcap(out)
    last_t = max(t for topic, t, _ in messages if topic == "/tf")
    rel = {
        m["child_frame_id"]: (m["parent_frame_id"], m)
        for topic, t, m in messages
        if topic == "/tf" and t == last_t
    }
    frame = "panda_hand"
    T = np.eye(4)
    while frame in rel:
        parent, m = rel[frame]
        T = _matrix(m) @ T
        frame = parent
    assert frame == scene.base_frame
    hand = scene.frame_names.index("panda_hand")
    np.testing.assert_allclose(T, scene.poses[-1, hand], atol=1e-9)


def _matrix(m: dict[str, Any]) -> np.ndarray[Any, Any]:
    x, y, z, w = (m["rotation"][k] for k in "xyzw")
    R = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = [m["translation"][k] for k in "xyz"]
    return T


def test_mcap_messages_validate_against_their_registered_schemas(
    scene: Scene, tmp_path: Path
) -> None:
    pytest.importorskip("mcap")
    jsonschema = pytest.importorskip("jsonschema")
    out = tmp_path / "panda.mcap"
    render(scene, "mcap", out, buffered=True)
    channels, messages = _read_mcap(out)
    seen = set()
    for topic, _, message in messages:
        schema = json.loads(channels[topic][1].data)
        if topic not in seen:  # one of each is enough; the writer builds all alike
            jsonschema.validate(message, schema)
            seen.add(topic)
    assert seen == set(channels)


# ------------------------------------------------------------------------------------------
# PNG
# ------------------------------------------------------------------------------------------
def test_png_shows_the_spheres_in_their_link_colours(scene: Scene, tmp_path: Path) -> None:
    from matplotlib.image import imread

    out = tmp_path / "panda.png"
    render(scene, "png", out)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    img = imread(out)
    assert img.shape[:2] == (640, 640)
    rgb = (img[..., :3] * 255).round().astype(int).reshape(-1, 3)
    present = 0
    for link in scene.links:
        if not link.n_spheres:
            continue
        target = np.array([round(255 * c) for c in link.color[:3]])
        # shaded surfaces darken/lighten the colour; look for close hues
        present += bool(np.any(np.abs(rgb - target).max(axis=1) < 40))
    assert present >= 8  # most links are visible from the default view


def test_png_sphere_polygons_match_a_simple_loop_over_the_grid(scene: Scene) -> None:
    """The PNG's spheres are quadrilaterals on a longitude × latitude grid: checked against a
    per-sphere loop, and the figure holds one polygon per quadrilateral."""
    from matplotlib.collections import PolyCollection

    from xrdf_tools.viz.png import draw_png, sphere_quads

    centres, radii = [], []
    for link in scene.links:
        T = scene.poses[0, link.frame_index]
        centres.extend(link.centers @ T[:3, :3].T + T[:3, 3])
        radii.extend(link.radii)
    u, v = np.linspace(0.0, 2.0 * np.pi, 18), np.linspace(0.0, np.pi, 10)

    def point(c: Any, r: float, i: int, j: int) -> Any:
        return c + r * np.array(
            [np.cos(u[i]) * np.sin(v[j]), np.sin(u[i]) * np.sin(v[j]), np.cos(v[j])]
        )

    want = [
        [point(c, r, i, j), point(c, r, i + 1, j), point(c, r, i + 1, j + 1), point(c, r, i, j + 1)]
        for c, r in zip(centres, radii, strict=True)
        for i in range(17)
        for j in range(9)
    ]
    got = sphere_quads(np.array(centres), np.array(radii))
    np.testing.assert_allclose(got, np.array(want), atol=1e-12)
    fig = draw_png(scene, legend="off")
    (coll,) = [c for c in fig.artists if isinstance(c, PolyCollection)]
    assert len(coll.get_facecolor()) == len(want) == 61 * 153


def test_png_of_10000_spheres_uses_coarser_spheres_within_the_polygon_budget() -> None:
    from xrdf_tools.viz.png import MAX_POLYGONS, sphere_quads

    rng = np.random.default_rng(0)
    centres, radii = rng.uniform(-0.5, 0.5, (10_000, 3)), rng.uniform(0.005, 0.03, 10_000)
    quads = sphere_quads(centres, radii)
    assert len(quads) % 10_000 == 0 and 10_000 < len(quads) <= MAX_POLYGONS
    per = len(quads) // 10_000
    # every corner of sphere k lies on its surface
    dist = np.linalg.norm(quads.reshape(10_000, per * 4, 3) - centres[:, None], axis=2)
    np.testing.assert_allclose(dist, np.repeat(radii[:, None], per * 4, axis=1), rtol=1e-12)


def test_png_is_framed_by_the_picture_given_to_render(scene: Scene, tmp_path: Path) -> None:
    from matplotlib.image import imread

    from xrdf_tools.viz import Picture
    from xrdf_tools.viz.png import VIEWS

    shots = {}
    for view in ("top", "side"):
        out = tmp_path / f"{view}.png"
        render(scene, "png", out, picture=Picture(view=VIEWS[view], legend="off", size_px=200))
        assert imread(out).shape[:2] == (200, 200)
        shots[view] = out.read_bytes()
    assert shots["top"] != shots["side"]


# ------------------------------------------------------------------------------------------
# Configurations files
# ------------------------------------------------------------------------------------------
def test_configurations_from_text_npy_and_yaml(tmp_path: Path, panda: tuple[Any, Xrdf]) -> None:
    urdf, xrdf = panda
    kin, _ = build_kinematic_model(urdf, xrdf)
    j1, j4 = kin.actuated_index("panda_joint1"), kin.actuated_index("panda_joint4")
    csv = tmp_path / "q.csv"
    csv.write_text("# two poses\npanda_joint1, panda_joint4\n0.5, -1.0\n-0.5, -2.0\n")
    Q = load_configurations(csv, kin, xrdf)
    assert Q.shape == (2, kin.n_actuated)
    assert Q[:, j1].tolist() == [0.5, -0.5] and Q[:, j4].tolist() == [-1.0, -2.0]
    fingers = kin.actuated_index("panda_finger_joint1")
    assert Q[0, fingers] == pytest.approx(0.04)  # held at the XRDF default

    npy = tmp_path / "q.npy"
    np.save(npy, np.zeros((3, 7)))
    assert load_configurations(npy, kin, xrdf).shape == (3, kin.n_actuated)

    yml = tmp_path / "q.yaml"
    yml.write_text("- {panda_joint2: 0.3}\n- [0, 0, 0, -1, 0, 1, 0]\n")
    Q = load_configurations(yml, kin, xrdf)
    assert Q[0, kin.actuated_index("panda_joint2")] == 0.3 and Q[1, j4] == -1.0

    bad = tmp_path / "bad.txt"
    bad.write_text("0 0 0\n")
    with pytest.raises(SourceError, match=r"bad\.txt:1: configuration 0 has 3 values"):
        load_configurations(bad, kin, xrdf)
    typo = tmp_path / "typo.csv"
    typo.write_text("panda_joint11\n0\n")
    with pytest.raises(SourceError, match=r"typo\.csv:1: joint 'panda_joint11'"):
        load_configurations(typo, kin, xrdf)


# ------------------------------------------------------------------------------------------
# CLI
# ------------------------------------------------------------------------------------------
def _viz(runner: CliRunner, panda_urdf: Path, *args: str) -> Any:
    return runner.invoke(app, ["viz", str(PANDA_XRDF), "--urdf", str(panda_urdf), *args])


def test_cli_png_and_summary(runner: CliRunner, panda_urdf: Path, tmp_path: Path) -> None:
    out = tmp_path / "p.png"
    r = _viz(runner, panda_urdf, "--png", str(out), "--meshes", "none")
    assert r.exit_code == 0, r.output
    assert out.stat().st_size > 10_000
    assert "61 spheres" in r.output and "1 sample(s)" in r.output


def test_cli_mcap_with_configs_and_colliding_only(
    runner: CliRunner, panda_urdf: Path, tmp_path: Path
) -> None:
    pytest.importorskip("mcap")
    configs = tmp_path / "q.txt"
    # default-like pose (free) and one with the hand folded onto the base (colliding)
    configs.write_text("0 -1.3 0 -2.5 0 1.5 0.8\n0 1.7 0 -3.0 0 0.0 0\n")
    out = tmp_path / "q.mcap"
    r = _viz(
        runner,
        panda_urdf,
        "--mcap",
        str(out),
        "--configs",
        str(configs),
        "--colliding-only",
        "--meshes",
        "none",
    )
    assert r.exit_code == 0, r.output
    _, messages = _read_mcap(out)
    logs = [m["message"] for topic, _, m in messages if topic == "/xrdf/collisions"]
    assert len(logs) == 2 and "configuration 1" in logs[1]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ([], "choose exactly one output"),
        (["--png", "a.png", "--mcap", "a.mcap"], "choose exactly one output"),
        (["--png", "a.png", "--samples", "3", "--configs", "q.txt"], "cannot be combined"),
        (["--png", "a.png", "--group", "nope"], "geometry group 'nope' is not defined"),
        (["--png", "missing_dir/a.png", "--meshes", "none"], "output directory does not exist"),
    ],
)
def test_cli_usage_errors_exit_2_with_one_line(
    runner: CliRunner,
    panda_urdf: Path,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    args: list[str],
    message: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    r = _viz(runner, panda_urdf, *args)
    assert r.exit_code == 2
    assert message in r.output and "Traceback" not in r.output
    assert not list(tmp_path.iterdir())  # nothing written, no temporary left


def test_cli_never_overwrites_an_input(runner: CliRunner, panda_urdf: Path, tmp_path: Path) -> None:
    copy = tmp_path / "panda.xrdf"
    copy.write_bytes(PANDA_XRDF.read_bytes())
    r = runner.invoke(app, ["viz", str(copy), "--urdf", str(panda_urdf), "--png", str(copy)])
    assert r.exit_code == 2 and "refusing to overwrite an input" in r.output
    assert copy.read_bytes() == PANDA_XRDF.read_bytes()


def test_cli_output_on_a_symlink_loop_is_one_line_not_a_traceback(
    runner: CliRunner, panda_urdf: Path, tmp_path: Path
) -> None:
    (tmp_path / "a.png").symlink_to("b.png")
    (tmp_path / "b.png").symlink_to("a.png")
    r = _viz(runner, panda_urdf, "--png", str(tmp_path / "a.png"))
    assert r.exit_code == 2, r.output
    assert r.output.strip().splitlines()[-1].startswith(f"error: {tmp_path / 'a.png'}: ")
    assert "Traceback" not in r.output and "symbolic links" in r.output


def test_cli_never_overwrites_a_mesh_of_the_robot(
    runner: CliRunner, panda_urdf: Path, tmp_path: Path
) -> None:
    """A mesh file the URDF names is an input too: an output on it is refused."""
    urdf, mesh = panda_copy_with_mesh(tmp_path, "visual/link0.dae")
    before = mesh.read_bytes()
    args = ["--urdf", str(urdf), "--package-path", f"example-robot-data={tmp_path}"]
    r = runner.invoke(app, ["viz", str(PANDA_XRDF), *args, "--png", str(mesh)])
    assert r.exit_code == 2, r.output
    assert f"{mesh}: refusing to overwrite an input" in r.output
    assert mesh.read_bytes() == before
    assert sorted(p.name for p in mesh.parent.iterdir()) == ["link0.dae"]  # no temporary left


@pytest.mark.parametrize(("flag", "module"), [("--rrd", "rerun"), ("--mcap", "mcap")])
def test_cli_missing_viz_extra_says_how_to_install(
    runner: CliRunner,
    panda_urdf: Path,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    flag: str,
    module: str,
) -> None:
    monkeypatch.setitem(sys.modules, module, None)  # makes `import module` fail
    r = _viz(runner, panda_urdf, flag, str(tmp_path / "out"))
    assert r.exit_code == 2
    assert 'pip install "xrdf-tools[viz]"' in r.output
    assert len(r.output.strip().splitlines()) == 1


def test_docs_show_a_small_png_made_by_the_tool() -> None:
    image = FIXTURES.parent / "docs" / "images" / "panda_spheres.png"
    data = image.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) < 200_000
    assert "images/panda_spheres.png" in (FIXTURES.parent / "docs" / "viz.md").read_text()


def test_core_imports_no_visualization_backend() -> None:
    code = (
        "import sys, xrdf_tools.cli, xrdf_tools.viz, xrdf_tools.viz.scene\n"
        "heavy = {'rerun', 'mcap', 'matplotlib', 'trimesh'} & set(sys.modules)\n"
        "print(sorted(heavy))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_cli_wrong_urdf_is_an_error_not_an_empty_picture(runner: CliRunner, tmp_path: Path) -> None:
    """The Panda spheres on the UR10e URDF: no sphere frame exists, so nothing could be drawn."""
    from tests.paths import UR10E_URDF

    out = tmp_path / "x.png"
    r = runner.invoke(
        app,
        [
            "viz",
            str(FIXTURES / "panda" / "panda.xrdf"),
            "--urdf",
            str(UR10E_URDF),
            "--png",
            str(out),
        ],
    )
    assert r.exit_code == 2
    assert "ur10e.urdf does not match this XRDF: c-space joint 'panda_joint1'" in r.output
    assert r.output.startswith(f"error: {FIXTURES / 'panda' / 'panda.xrdf'}:")
    assert not out.exists()


@pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_FSIZE and SIGXFSZ as on Linux")
@pytest.mark.parametrize("target", ["--rrd", "--mcap"])
def test_a_full_disk_is_one_clean_error_and_leaves_nothing(
    runner: CliRunner, tmp_path: Path, target: str
) -> None:
    """The file-size limit makes every write past 4 KiB fail like a full disk (EFBIG), for our
    writer and for any library writing on its own: one line naming the output, exit 2, no hang,
    no temporary file left."""
    pytest.importorskip("rerun" if target == "--rrd" else "mcap")
    demo = FIXTURES / "demo_arm"
    xrdf = tmp_path / "demo.xrdf"
    made = runner.invoke(
        app,
        [
            "convert",
            str(demo / "demo_arm.urdf"),
            "--srdf",
            str(demo / "demo_arm.srdf"),
            "-o",
            str(xrdf),
        ],
    )
    assert made.exit_code == 0, made.output
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    out = out_dir / ("demo.rrd" if target == "--rrd" else "demo.mcap")
    script = (
        "import resource, signal, sys\n"
        "signal.signal(signal.SIGXFSZ, signal.SIG_IGN)\n"
        "resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))\n"
        "from xrdf_tools.cli import main\n"
        "sys.argv = ['xrdf', *sys.argv[1:]]\n"
        "main()\n"
    )
    args = ["viz", str(xrdf), "--urdf", str(demo / "demo_arm.urdf"), "-n", "20", target, str(out)]
    env = {**__import__("os").environ, "PYTHONPATH": str(FIXTURES.parent)}
    res = subprocess.run(
        [sys.executable, "-c", script, *args], capture_output=True, text=True, env=env, timeout=120
    )
    assert res.returncode == 2, res.stderr
    assert "Traceback" not in res.stderr
    (line,) = [x for x in res.stderr.splitlines() if x.startswith("error:")]
    assert line.startswith(f"error: {out}: cannot write") and ".tmp" not in line
    assert list(out_dir.iterdir()) == []


def test_png_draws_names_with_dollar_signs_as_written(runner: CliRunner, tmp_path: Path) -> None:
    """A robot or link name with ``$`` signs (``r$x``, ``arm$\\undefinedcommand$``) is drawn
    as written: matplotlib's math text would italicise what lies between two of them, or stop
    at an unknown command."""
    from xrdf_tools.viz.png import draw_png

    urdf, name = dollar_robot(tmp_path)
    xrdf = tmp_path / "r.xrdf"
    args = ["convert", str(urdf), "--fit-spheres", "--per-link", "1", "-n", "50", "-o", str(xrdf)]
    assert runner.invoke(app, args).exit_code == 0
    out = tmp_path / "r.png"
    r = runner.invoke(app, ["viz", str(xrdf), "--urdf", str(urdf), "--png", str(out)])
    assert r.exit_code == 0, r.output
    assert out.stat().st_size > 0
    scene = build_scene(load_urdf(urdf), load_xrdf(xrdf))
    fig = draw_png(scene)
    from matplotlib.text import Text

    texts = [t for t in fig.findobj(Text) if "$" in t.get_text()]
    assert {t.get_text() for t in texts} >= {name}
    assert all(not t._parse_math for t in texts)


@pytest.mark.parametrize(("view", "depth"), [("front", "x"), ("side", "y"), ("top", "z")])
def test_png_of_a_view_along_an_axis_draws_no_ticks_of_that_axis(
    scene: Scene, view: str, depth: str
) -> None:
    """`--view front` drew the x axis end-on: its ticks and 'x (m)' piled up on one point at
    the picture's edge, unreadable. The axis the camera looks along has no ticks or label; the
    two others keep theirs, and the three-quarter view keeps all three."""
    from xrdf_tools.viz.png import VIEWS, draw_png

    ax = draw_png(scene, view=VIEWS[view], legend="off").axes[0]
    for axis in "xyz":
        ticks = getattr(ax, f"get_{axis}ticks")()
        label = getattr(ax, f"get_{axis}label")()
        assert (len(ticks) == 0 and label == "") if axis == depth else (len(ticks) and label)
    iso = draw_png(scene, legend="off").axes[0]
    assert all(len(getattr(iso, f"get_{a}ticks")()) for a in "xyz")
