"""``--method morphit``: MorphIt (``morphit-rs``) fits each link's solid at our counts, seeds
and bounds (:mod:`xrdf_tools.spheres.morphit`), on real Panda meshes."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from tests.robots import robot_urdf
from tests.spheres.test_spheres_bound import _max_protrusion
from xrdf_tools.cli import app
from xrdf_tools.spheres.count_policy import CountPolicy
from xrdf_tools.spheres.fit import SphereFitter, _rounded
from xrdf_tools.spheres.geometry import LinkGeometry, load_link_geometry
from xrdf_tools.spheres.morphit import PRESET, inscribed, morphit_seed, pack
from xrdf_tools.spheres.robot_fit import FitResult, fit_robot, solid_key
from xrdf_tools.util.errors import MissingDependencyError, XrdfToolsError
from xrdf_tools.xrdf.io import load_xrdf
from xrdf_tools.xrdf.model import Sphere

mi = pytest.importorskip("morphit_rs")

LINKS = ["panda_link0", "panda_hand"]


@pytest.fixture(scope="module", autouse=True)
def _one_thread() -> None:
    """A shared machine: MorphIt on one thread (its results do not depend on it)."""
    mi.set_num_threads(1)


@pytest.fixture(scope="module")
def panda() -> Path:
    return robot_urdf("panda")


@pytest.fixture(scope="module")
def geoms(panda: Path) -> dict[str, LinkGeometry]:
    return load_link_geometry(panda, links=LINKS)[0]


def _fit(geoms: dict[str, LinkGeometry], method: str = "morphit", **kw: Any) -> FitResult:
    return fit_robot("panda.urdf", geometry=geoms, method=method, **kw)


def _morphit_alone(solid: Any, k: int, seed: int) -> tuple[Sphere, ...]:
    """MorphIt's own spheres for ``solid``, rounded as the adapter rounds them."""
    mesh = mi.Mesh.from_arrays(
        np.asarray(solid.vertices, dtype=np.float64), np.asarray(solid.faces, dtype=np.uint32)
    )
    result = mi.pack(mesh, mi.Config.preset(PRESET, num_spheres=k, seed=seed))
    return tuple(_rounded(c, r) for c, r in zip(result.centers, result.radii, strict=True))


def test_per_link_counts_are_given_and_the_spheres_are_morphit_s_own(
    geoms: dict[str, LinkGeometry],
) -> None:
    """Without bounds the spheres are MorphIt's, seeded from the seed and the solid's content
    (one 64-bit seed from the two words of our fit seed)."""
    result = _fit(geoms, counts=CountPolicy(per_link={"panda_link0": 3, "panda_hand": 5}), seed=7)
    assert {k: len(v) for k, v in result.spheres.items()} == {"panda_link0": 3, "panda_hand": 5}
    solid = geoms["panda_hand"].solid
    seed = morphit_seed([7, int(solid_key(solid)[:8], 16)])
    assert seed == (7 << 32) | int(solid_key(solid)[:8], 16)
    assert result.spheres["panda_hand"] == _morphit_alone(solid, 5, seed)
    again = _fit(geoms, counts=CountPolicy(per_link=3), seed=7)
    other = _fit(geoms, counts=CountPolicy(per_link=3), seed=8)
    assert again.spheres["panda_link0"] == result.spheres["panda_link0"]
    assert other.spheres["panda_link0"] != result.spheres["panda_link0"]


@pytest.mark.slow
def test_counts_by_total_and_by_default_are_the_ones_our_method_gives(
    geoms: dict[str, LinkGeometry],
) -> None:
    for policy in (CountPolicy(count=9), CountPolicy()):
        ours = _fit(geoms, "ours", counts=policy).spheres
        theirs = _fit(geoms, counts=policy).spheres
        assert {k: len(v) for k, v in theirs.items()} == {k: len(v) for k, v in ours.items()}
        assert theirs != ours
    assert sum(len(v) for v in theirs.values()) > 2


def test_spheres_crossing_a_clip_plane_are_inscribed_in_it_and_the_half_space() -> None:
    """Against the rule worked out sphere by sphere: a sphere crossing a plane becomes the
    largest sphere inside it and the kept side; the others are unchanged."""
    rng = np.random.default_rng(3)
    centers = rng.uniform(-0.1, 0.1, (40, 3))
    radii = rng.uniform(0.005, 0.06, 40)
    planes = [((0.0, 0.6, 0.8), 0.01), ((1.0, 0.0, 0.0), -0.05)]
    got_c, got_r = inscribed(centers, radii, planes)
    crossed = 0
    for i, (c, r) in enumerate(zip(centers, radii, strict=True)):
        for (nx, ny, nz), d in planes:
            normal = np.array([nx, ny, nz])
            gap = float(normal @ c) - d
            if r > gap:
                c, r, crossed = c + normal * (r - gap) / 2, (r + gap) / 2, crossed + 1
        assert np.allclose(got_c[i], c, rtol=0, atol=1e-12) and abs(got_r[i] - r) < 1e-12
        # inside the original sphere and on the kept side of every plane
        assert np.linalg.norm(got_c[i] - centers[i]) + got_r[i] <= radii[i] + 1e-12
        for (nx, ny, nz), d in planes:
            assert float(np.dot((nx, ny, nz), got_c[i])) - got_r[i] >= d - 1e-12
    assert crossed > 0 and (got_r < 0).any() and (got_r == radii).any()


def test_a_clip_plane_and_a_protrusion_bound_are_hard_bounds(
    geoms: dict[str, LinkGeometry],
) -> None:
    clip = ((0.0, 0.0, 1.0), 0.03)
    result = _fit(geoms, counts=CountPolicy(per_link=6), clips={"panda_link0": [clip]})
    link0 = result.spheres["panda_link0"]
    assert 1 <= len(link0) <= 6
    assert all(s.center[2] - s.radius >= 0.03 - 1e-9 for s in link0)
    free = _fit(geoms, counts=CountPolicy(per_link=6)).spheres["panda_link0"]
    assert any(s.center[2] - s.radius < 0.03 for s in free)  # the plane did bind

    tau = 0.002
    bound = _fit(geoms, counts=CountPolicy(per_link=6), max_protrusion=tau).spheres
    solid = geoms["panda_hand"].solid
    fitter = SphereFitter(solid, seed=[0, int(solid_key(solid)[:8], 16)], max_protrusion=tau)
    hand = bound["panda_hand"]
    assert len(hand) == 6
    # as for our fits: the grid's level set is interpolated (half a cell), radii rounded up
    assert _max_protrusion(solid, hand) <= tau + fitter.sdf.step / 2 + 1e-4
    loose = _fit(geoms, counts=CountPolicy(per_link=6)).spheres["panda_hand"]
    assert sum(s.radius for s in hand) < sum(s.radius for s in loose)


def test_fewer_spheres_than_asked_are_said(geoms: dict[str, LinkGeometry]) -> None:
    """Two clip planes leave a 0.2 mm slab of ``panda_link0``: MorphIt prunes spheres there
    and what it returns has no room for 0.1 mm of radius; the link keeps what fits and a
    warning says how many of the four and why."""
    slab = [((0.0, 0.0, 1.0), 0.05), ((0.0, 0.0, -1.0), -0.0502)]
    result = _fit(geoms, counts=CountPolicy(per_link=4), clips={"panda_link0": slab})
    kept = result.spheres.get("panda_link0", ())
    assert len(kept) < 4
    assert all(
        0.05 - 1e-9 <= s.center[2] - s.radius <= s.center[2] + s.radius <= 0.0502 + 1e-9
        for s in kept
    )
    said = [d for d in result.diagnostics if d.rule == "spheres-morphit-dropped"]
    assert len(said) == 1 and said[0].message.startswith(
        f"link 'panda_link0': {len(kept)} of the 4 spheres asked of MorphIt kept: "
    )
    assert "under 0.1 mm of radius within its clip planes" in said[0].message


def test_a_solid_morphit_refuses_is_an_error_of_one_line() -> None:
    import trimesh

    flat = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], process=False)
    with pytest.raises(XrdfToolsError, match=r"^MorphIt cannot fit it: mesh is flat"):
        pack(flat, 3, 0)


def test_an_unknown_method_and_a_searched_bound_are_refused(
    geoms: dict[str, LinkGeometry],
) -> None:
    with pytest.raises(XrdfToolsError, match="ours, morphit"):
        _fit(geoms, "greedy")
    with pytest.raises(XrdfToolsError, match="count_coverage"):
        _fit(geoms, counts=CountPolicy(per_link=2, count_coverage=0.95))


def test_without_morphit_rs_the_error_names_the_extra(
    geoms: dict[str, LinkGeometry],
    panda: Path,
    runner: CliRunner,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setitem(sys.modules, "morphit_rs", None)  # import fails as if not installed
    with pytest.raises(MissingDependencyError, match=r'pip install "xrdf-tools\[morphit\]"'):
        _fit(geoms)
    assert _fit(geoms, "ours", counts=CountPolicy(per_link=1)).spheres
    for args in (
        ["spheres", str(panda), "--method", "morphit"],
        ["convert", str(panda), "--fit-spheres", "--method", "morphit"],
    ):
        res = runner.invoke(app, args)
        assert res.exit_code == 2, res.output
        lines = res.stderr.strip().splitlines()
        assert len(lines) == 1 and "'morphit' extra" in lines[0], res.stderr
        assert 'pip install "xrdf-tools[morphit]"' in lines[0]


def test_spheres_cli_fits_with_morphit_and_prints_the_metrics(
    panda: Path, runner: CliRunner, tmp_path: Path
) -> None:
    out = tmp_path / "p.xrdf"
    args = ["spheres", str(panda), "--links", "panda_hand", "--per-link", "4"]
    res = runner.invoke(app, [*args, "--method", "morphit", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "panda_hand" in res.stdout and "coverage" in res.stdout and "overall" in res.stdout
    spheres = load_xrdf(out).resolved_spheres("panda_collision_spheres")["panda_hand"]
    assert len(spheres) == 4
    ours = tmp_path / "o.xrdf"
    assert runner.invoke(app, [*args, "-o", str(ours)]).exit_code == 0
    assert load_xrdf(ours).resolved_spheres("panda_collision_spheres")["panda_hand"] != spheres


@pytest.mark.slow
def test_convert_fit_spheres_with_morphit(panda: Path, runner: CliRunner, tmp_path: Path) -> None:
    res = runner.invoke(app, ["convert", str(panda), "--method", "morphit", "-o", "-"])
    assert res.exit_code == 2 and "--fit-spheres" in res.stderr
    out = tmp_path / "p.xrdf"
    args = ["convert", str(panda), "--fit-spheres", "--per-link", "2", "-n", "300"]
    res = runner.invoke(app, [*args, "--method", "morphit", "-o", str(out)])
    assert res.exit_code == 0, res.output
    x = load_xrdf(out)
    spheres = x.world_collision_spheres()
    assert spheres and all(len(v) == 2 for v in spheres.values() if v)
    geoms = load_link_geometry(panda, links=["panda_link3"])[0]
    seed = morphit_seed([0, int(solid_key(geoms["panda_link3"].solid)[:8], 16)])
    assert tuple(spheres["panda_link3"]) == _morphit_alone(geoms["panda_link3"].solid, 2, seed)


def test_the_commands_offer_exactly_the_library_s_methods() -> None:
    """``--method``'s choices (the CLI keeps its own list: the library's module imports numpy,
    which the command table must not) are the methods the library fits with."""
    from xrdf_tools.cli.commands.spheres import FitMethod
    from xrdf_tools.spheres.morphit import METHODS

    assert tuple(m.value for m in FitMethod) == METHODS
