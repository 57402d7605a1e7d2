"""Patterns found by converting cuRobo's real classic-layout configs (franka.yml, iiwa.yml, …).

The real files are not in the repository; ``fixtures/curobo_classic/ur10e_real_patterns.yml`` and
``spheres/ur10e_shared.yml`` reproduce their shape in a few lines.
"""

from __future__ import annotations

from tests.paths import FIXTURES, UR10E_URDF
from xrdf_tools.convert.core import ConvertOptions, convert_files
from xrdf_tools.diagnostics import Diagnostic, Severity
from xrdf_tools.xrdf.model import Sphere, Xrdf

CLASSIC = FIXTURES / "curobo_classic"
CONFIG = CLASSIC / "ur10e_real_patterns.yml"
SPHERES = CLASSIC / "spheres" / "ur10e_shared.yml"


def _convert() -> tuple[Xrdf, dict[str, list[Diagnostic]]]:
    x, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=CONFIG))
    rules: dict[str, list[Diagnostic]] = {}
    for d in diags:
        rules.setdefault(d.rule, []).append(d)
    return x, rules


def _spheres(x: Xrdf) -> dict[str, tuple[Sphere, ...]]:
    assert x.geometry is not None
    return dict(x.geometry["ur10e_collision_spheres"].spheres)


def test_repeated_keys_are_warnings_and_the_last_value_wins_like_pyyaml() -> None:
    # cuRobo's franka.yml repeats usd_flip_joints; cuRobo (PyYAML) keeps the last value, so
    # the file must convert instead of failing with a duplicate-key error.
    x, rules = _convert()
    dups = {(d.path, d.line): d for d in rules["convert-duplicate-key"]}
    assert (str(CONFIG), 7) in dups and "usd_flip_joints" in dups[(str(CONFIG), 7)].message
    assert "first on line 6" in dups[(str(CONFIG), 7)].message
    assert (str(CONFIG), 20) in dups  # cspace.max_jerk: 500 then 600
    assert all(d.severity is Severity.WARNING for d in rules["convert-duplicate-key"])
    assert x.cspace is not None and x.cspace.jerk_limits == (600.0,) * 6
    # a repeated link in the sphere file: reported there, its last list used
    assert (str(SPHERES), 14) in dups
    spheres = _spheres(x)
    ((center, radius),) = [(s.center, s.radius) for s in spheres["forearm_link"]]
    assert center == (-0.2855, 0.0, 0.03) and radius == 0.05


def test_spheres_of_another_robot_in_a_shared_file_are_one_info_not_unknown_links() -> None:
    # cuRobo's iiwa.yml uses spheres/iiwa_allegro.yml: the hand links are not in iiwa.urdf and
    # not in collision_link_names, so cuRobo never reads them; no did-you-mean noise per link.
    x, rules = _convert()
    unknown = [d for d in rules["convert-unknown-link"] if d.path == str(SPHERES)]
    assert [d.line for d in unknown] == [26]  # only wrist_3_lnk, which IS a collision link
    assert "did you mean 'wrist_3_link'" in unknown[0].message
    unused = {d.severity: d for d in rules["convert-unused-spheres"]}
    foreign = unused[Severity.INFO]
    assert foreign.path == str(SPHERES) and foreign.line == 20
    assert "2 link(s)" in foreign.message and "palm_link, index_link_1" in foreign.message
    # a URDF link with spheres that is not a collision link keeps its own warning
    assert "'camera_mount'" in unused[Severity.WARNING].message
    spheres = _spheres(x)
    assert set(spheres) == {"shoulder_link", "upper_arm_link", "forearm_link"}
    # the collision_link_names typo is still reported in the config itself
    assert any(
        d.path == str(CONFIG) and "'wrist_3_lnk' (collision link)" in d.message
        for d in rules["convert-unknown-link"]
    )
