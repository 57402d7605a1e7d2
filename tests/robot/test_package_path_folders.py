"""A package split over several folders: ``--package-path NAME=DIR`` given once per folder.

iCub (icub-models) names every mesh ``package://iCub/...``, but the files sit in two folders:
``iCub_manual`` (its package.xml says ``iCub``) holds ``meshes/``, ``iCub_creo2urdf`` holds
``meshes_creo2urdf/``. The fixture below is that layout in small: package ``robo``, the hand
mesh in ``manual/meshes``, the torso mesh in ``generated/meshes_gen``, neither folder named
``robo`` and the URDF far from both (the nearby search finds neither).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.export.curobo_assets import mesh_root, unserved_note
from xrdf_tools.robot import link_geometry as lg
from xrdf_tools.robot.packages import PackageResolver, parse_package_paths
from xrdf_tools.robot.xacro_source import expand_xacro, load_robot
from xrdf_tools.util.errors import XrdfToolsError

HAND = "package://robo/meshes/hand.stl"
TORSO = "package://robo/meshes_gen/torso.stl"


def _box(path: Path, size: float) -> None:
    import trimesh

    path.parent.mkdir(parents=True, exist_ok=True)
    trimesh.creation.box((size, size, size)).export(path)


def _robot_text(hand: str = HAND, torso: str = TORSO) -> str:
    links = "".join(
        f'<link name="{n}"><collision><geometry><mesh filename="{uri}"/></geometry>'
        "</collision></link>"
        for n, uri in (("torso", torso), ("hand", hand))
    )
    joint = (
        '<joint name="j" type="revolute"><parent link="torso"/><child link="hand"/>'
        '<origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
    )
    return f'<robot name="r">{links}{joint}</robot>'


@pytest.fixture
def split(tmp_path: Path) -> tuple[Path, Path, Path]:
    """``(urdf, manual, generated)``: package ``robo`` split over two folders."""
    manual, generated = tmp_path / "ws" / "manual", tmp_path / "ws" / "generated"
    _box(manual / "meshes" / "hand.stl", 0.1)
    _box(generated / "meshes_gen" / "torso.stl", 0.2)
    (manual / "package.xml").write_text("<package><name>robo</name></package>")
    urdf = tmp_path / "robot" / "r.urdf"
    urdf.parent.mkdir()
    urdf.write_text(_robot_text())
    return urdf, manual, generated


def test_each_file_is_found_in_the_folder_that_holds_it(split: tuple[Path, Path, Path]) -> None:
    urdf, manual, generated = split
    resolver = PackageResolver(urdf, {"robo": [str(manual), generated]})
    assert resolver.resolve_uri(HAND) == manual / "meshes" / "hand.stl"
    assert resolver.resolve_uri(TORSO) == generated / "meshes_gen" / "torso.stl"
    assert resolver.find("robo") == manual  # $(find robo): the first folder
    robot = load_robot(urdf, package_paths={"robo": (manual, str(generated))})
    geometry = lg.link_geometry(robot, "collision")
    assert {n: (len(g.parts), g.failures) for n, g in geometry.items()} == {
        "torso": (1, ()),
        "hand": (1, ()),
    }


def test_the_first_folder_given_that_holds_a_file_wins(split: tuple[Path, Path, Path]) -> None:
    """The same file in both folders: the order of the options decides, each way."""
    urdf, manual, generated = split
    _box(generated / "meshes" / "hand.stl", 0.4)  # a bigger hand in the second folder
    sizes = {}
    for order in ((manual, generated), (generated, manual)):
        robot = load_robot(urdf, package_paths={"robo": [str(d) for d in order]})
        (part,) = lg.link_geometry(robot, "collision")["hand"].parts
        sizes[order[0].name] = float(part.mesh.extents[0])
        (torso,) = lg.link_geometry(robot, "collision")["torso"].parts
        assert torso.file == str(generated / "meshes_gen" / "torso.stl")
    assert sizes == pytest.approx({"manual": 0.1, "generated": 0.4})


def test_the_option_repeated_keeps_the_order_and_each_folder_once(tmp_path: Path) -> None:
    for d in ("a", "b"):
        (tmp_path / d).mkdir()
    a, b = str(tmp_path / "a"), str(tmp_path / "b")
    specs = [f"robo={b}", f"other={a}", f"robo={a}", f"robo={b}"]
    assert parse_package_paths(specs) == {"robo": (b, a, b), "other": (a,)}
    resolver = PackageResolver(tmp_path, parse_package_paths(specs))
    assert resolver.find("robo") == Path(b)


def test_spheres_fits_both_halves_with_the_option_given_per_folder(
    runner: CliRunner, split: tuple[Path, Path, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Before, only one DIR per package counted (the last given): the other half's meshes
    were missing (exit 2). Relative DIRs are taken from the current directory."""
    urdf, manual, _ = split
    monkeypatch.chdir(manual.parent)
    out = urdf.parent / "r.xrdf"
    args = ["spheres", str(urdf), "--package-path", "robo=manual"]
    res = runner.invoke(app, [*args, "--package-path", "robo=generated", "-o", str(out)])
    assert res.exit_code == 0, res.output
    text = out.read_text()
    assert "torso:" in text and "hand:" in text


def test_a_mesh_in_no_folder_names_every_folder_tried(
    runner: CliRunner, split: tuple[Path, Path, Path]
) -> None:
    urdf, manual, generated = split
    urdf.write_text(_robot_text(torso="package://robo/meshes_gen/gone.stl"))
    args = ["spheres", str(urdf), "-o", str(urdf.parent / "r.xrdf")]
    args += ["--package-path", f"robo={generated}", "--package-path", f"robo={manual}"]
    res = runner.invoke(app, args)
    assert res.exit_code == 2
    message = " ".join(res.output.split())
    tried = f"{generated / 'meshes_gen' / 'gone.stl'}, {manual / 'meshes_gen' / 'gone.stl'}"
    where = f"any of the 2 --package-path directories of 'robo' (looked for, in order: {tried})"
    assert where in message
    assert "--package-path robo=DIR once per folder" in message
    assert not (urdf.parent / "r.xrdf").exists()
    one = PackageResolver(urdf, {"robo": str(manual)})  # one folder: the hint to repeat it
    with pytest.raises(XrdfToolsError, match="takes --package-path robo=DIR once per folder"):
        one.resolve_uri(TORSO)


def test_find_gives_the_first_folder_in_a_xacro(
    runner: CliRunner, split: tuple[Path, Path, Path]
) -> None:
    urdf, manual, generated = split
    xacro = urdf.with_suffix(".urdf.xacro")
    xacro.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="a">'
        '<collision><geometry><mesh filename="file://$(find robo)/meshes/hand.stl"/>'
        "</geometry></collision></link></robot>"
    )
    text = expand_xacro(xacro, package_paths={"robo": [manual, generated]})
    assert f"file://{manual}/meshes/hand.stl" in text
    args = ["expand", str(xacro), "--package-path", f"robo={generated}"]
    res = runner.invoke(app, [*args, "--package-path", f"robo={manual}"])
    assert res.exit_code == 0, res.output
    assert f"file://{generated}/meshes/hand.stl" in res.stdout


def test_export_names_the_folders_of_a_split_package(split: tuple[Path, Path, Path]) -> None:
    """cuRobo joins every mesh name to one asset_root_path: a split package cannot be served;
    the note names both folders and the one folder to make. Made so, nothing is unserved."""
    urdf, manual, generated = split
    root = mesh_root(load_robot(urdf, package_paths={"robo": [manual, generated]}))
    assert root.split == (
        ("robo", ((str(generated), ("meshes_gen",)), (str(manual), ("meshes",)))),
    )
    assert root.misnamed == ()
    note = unserved_note(root)
    assert "Package 'robo' is split over 2 folders" in note
    links = f"{generated / 'meshes_gen'} {manual / 'meshes'}"
    assert f"ln -s {links} DIR/robo/)" in note and "--package-path robo=DIR/robo" in note
    merged = urdf.parent.parent / "merged" / "robo"
    merged.mkdir(parents=True)
    for target in (generated / "meshes_gen", manual / "meshes"):
        (merged / target.name).symlink_to(target)
    root = mesh_root(load_robot(urdf, package_paths={"robo": merged}))
    assert root.directory == merged.parent and root.unserved == () and root.split == ()


def test_a_file_in_none_of_many_folders_names_a_few_of_them(
    split: tuple[Path, Path, Path],
) -> None:
    """1,000 --package-path folders, none holding the file: the error named every one of
    them on one 52 kB line; now the first eight and how many more."""
    urdf, manual, _ = split
    many = [manual.parent / f"d{i}" for i in range(1000)]
    for folder in many:
        folder.mkdir()
    resolver = PackageResolver(urdf, {"robo": many})
    with pytest.raises(XrdfToolsError) as caught:
        resolver.resolve_uri(HAND)
    message = str(caught.value)
    assert "any of the 1000 --package-path directories of 'robo'" in message
    assert str(many[7] / "meshes" / "hand.stl") in message and "and 992 more" in message
    assert str(many[8] / "meshes" / "hand.stl") not in message and len(message) < 2000


def test_a_package_name_with_a_slash_is_refused(split: tuple[Path, Path, Path]) -> None:
    """``--package-path robo/meshes=DIR`` could never match (``package://robo/...`` names
    'robo') and was dropped without a word: the robot's meshes were then 'not found'."""
    _, manual, _ = split
    with pytest.raises(XrdfToolsError, match="a package name holds no '/'"):
        parse_package_paths([f"robo/meshes={manual}"])
