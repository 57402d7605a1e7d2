"""The library is pure and safe to share between threads.

Calling the public API (load, convert with fitted spheres, lint, diff, the self-collision
report and its plot, sphere fitting and coverage, the PNG picture) prints nothing, leaves the
process's global state as it was (environment, working directory, warnings filters, numpy's
error state, logging, matplotlib's backend and rcParams) and writes only the files it is
asked to. Two threads working on different robots get the results one thread gets."""

from __future__ import annotations

import logging
import os
import sys
import threading
import warnings
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.paths import FIXTURES
from xrdf_tools.convert.core import ConvertOptions
from xrdf_tools.convert.pipeline import FitOptions, MaskOptions, convert_robot
from xrdf_tools.diff import diff_xrdf
from xrdf_tools.lint import lint
from xrdf_tools.report.build import self_collision_report
from xrdf_tools.report.render import render_json, write_heatmap
from xrdf_tools.robot.kinematics import build_kinematic_model
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.spheres import coverage_for_xrdf, fit_link_spheres
from xrdf_tools.viz import build_scene, render, sample_configurations
from xrdf_tools.xrdf.io import dump_xrdf, load_xrdf

pytest.importorskip("trimesh")
pytest.importorskip("matplotlib")

#: Two different robots from the bundled fixtures: meshes, and primitives with a mimic joint.
ROBOTS = {
    "demo_arm": FIXTURES / "demo_arm" / "demo_arm.urdf",
    "three_link_mimic": FIXTURES / "urdf" / "three_link_mimic.urdf",
}
SAMPLES = 2000


def _global_state() -> dict[str, Any]:
    import matplotlib

    return {
        "environ": dict(os.environ),
        "cwd": os.getcwd(),
        "warnings": list(warnings.filters),
        "numpy errors": np.geterr(),
        "numpy print": np.get_printoptions(),
        "logging": (logging.root.level, list(logging.root.handlers), logging.root.manager.disable),
        "matplotlib backend": matplotlib.get_backend(),
        "rcParams": dict(matplotlib.rcParams),
        "recursion limit": sys.getrecursionlimit(),
    }


def _files(folder: Path) -> set[Path]:
    return {p for p in folder.rglob("*") if p.is_file()}


@pytest.fixture(scope="module")
def converted(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    """Each robot converted once, with fitted spheres and a computed mask: the XRDF text."""
    out = {}
    for name, urdf in ROBOTS.items():
        result = convert_robot(
            urdf,
            ConvertOptions(),
            fit=FitOptions(per_link=3),
            mask=MaskOptions(samples=SAMPLES),
        )
        out[name] = result.text
    return out


def _report_json(name: str, text: str) -> str:
    robot = load_robot(ROBOTS[name])
    return render_json(self_collision_report(robot, _xrdf(text), samples=SAMPLES, seed=1))


def _fit(name: str) -> str:
    spheres, diags = fit_link_spheres(ROBOTS[name], per_link=2, seed=3)
    return repr((sorted(spheres.items()), [d.message for d in diags]))


def _lint(name: str, text: str, folder: Path) -> str:
    path = folder / f"{name}.xrdf"
    path.write_text(text)
    return repr([(d.rule, d.line, d.message) for d in lint([path], urdf=ROBOTS[name])])


def _coverage(name: str, text: str) -> str:
    summary = coverage_for_xrdf(ROBOTS[name], _xrdf(text), samples=2000)
    return repr(sorted((link, m.coverage) for link, m in summary.links.items()))


def _pictures(name: str, text: str, folder: Path) -> bytes:
    """The PNG of the spheres and the PNG of the report's matrix, as bytes."""
    robot = load_robot(ROBOTS[name])
    xrdf = _xrdf(text)
    kin, _ = build_kinematic_model(robot, xrdf)
    scene = build_scene(robot, xrdf, sample_configurations(kin, xrdf, 1), meshes="none")
    png, matrix = folder / f"{name}.png", folder / f"{name}_matrix.png"
    render(scene, "png", png)
    write_heatmap(self_collision_report(robot, xrdf, samples=500), matrix)
    return png.read_bytes() + matrix.read_bytes()


def _xrdf(text: str) -> Any:
    from xrdf_tools.xrdf.io import parse_xrdf

    return parse_xrdf(text)


def _jobs(converted: dict[str, str], folder: Path) -> list[tuple[str, Callable[[], object]]]:
    jobs: list[tuple[str, Callable[[], object]]] = []
    for name, text in converted.items():
        sub = folder / name
        sub.mkdir(parents=True, exist_ok=True)
        jobs += [
            (f"report {name}", lambda n=name, t=text: _report_json(n, t)),
            (f"fit {name}", lambda n=name: _fit(n)),
            (f"lint {name}", lambda n=name, t=text, d=sub: _lint(n, t, d)),
            (f"coverage {name}", lambda n=name, t=text: _coverage(n, t)),
            (f"pictures {name}", lambda n=name, t=text, d=sub: _pictures(n, t, d)),
        ]
    return jobs


@pytest.mark.slow
def test_public_api_prints_nothing_and_leaves_the_process_as_it_was(
    converted: dict[str, str],
    tmp_path: Path,
    capfd: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(tmp_path)
    fixtures_before = {p: p.stat().st_mtime_ns for p in _files(FIXTURES)}
    before = _global_state()
    capfd.readouterr()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _, job in _jobs(converted, tmp_path / "out"):
            job()
        a, b = (_xrdf(t) for t in converted.values())
        diff_xrdf(a, b)
        dump_xrdf(load_xrdf(tmp_path / "out" / "demo_arm" / "demo_arm.xrdf"))
    out, err = capfd.readouterr()
    assert (out, err) == ("", "")
    assert [str(w.message) for w in caught] == []
    assert _global_state() == before
    assert {p: p.stat().st_mtime_ns for p in _files(FIXTURES)} == fixtures_before
    names = {p.relative_to(tmp_path).as_posix() for p in _files(tmp_path)}
    asked = {f"out/{n}/{n}{suffix}" for n in ROBOTS for suffix in (".xrdf", ".png", "_matrix.png")}
    assert names == asked


@pytest.mark.slow
def test_two_threads_on_different_robots_give_the_serial_results(
    converted: dict[str, str], tmp_path: Path
) -> None:
    serial = {label: job() for label, job in _jobs(converted, tmp_path / "serial")}
    jobs = _jobs(converted, tmp_path / "threads")
    with ThreadPoolExecutor(max_workers=2) as pool:
        # each robot's jobs interleaved with the other's
        futures = {label: pool.submit(job) for label, job in jobs}
        threaded = {label: f.result() for label, f in futures.items()}
    assert threaded.keys() == serial.keys()
    for label, value in serial.items():
        assert threaded[label] == value, label


def test_worker_environment_is_restored_when_counts_overlap_in_threads(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Two counts started from two threads at once: the first to finish does not restore the
    environment under the second, and the last leaves it as it was before either."""
    from xrdf_tools.selfcollision.engine.jobs import _BLAS_VARS, _one_blas_thread

    monkeypatch.setenv("OMP_NUM_THREADS", "7")
    monkeypatch.delenv("MKL_NUM_THREADS", raising=False)
    first_in, second_in, first_out = threading.Event(), threading.Event(), threading.Event()
    seen: dict[str, dict[str, str | None]] = {}

    def first() -> None:
        with _one_blas_thread():
            first_in.set()
            second_in.wait(5)
        first_out.set()

    def second() -> None:
        first_in.wait(5)
        with _one_blas_thread():
            second_in.set()
            first_out.wait(5)
            seen["after the first left"] = {v: os.environ.get(v) for v in _BLAS_VARS}

    threads = [threading.Thread(target=first), threading.Thread(target=second)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(10)
    assert seen["after the first left"] == dict.fromkeys(_BLAS_VARS, "1")
    assert os.environ.get("OMP_NUM_THREADS") == "7"
    assert "MKL_NUM_THREADS" not in os.environ


def test_xacro_expansions_in_two_threads_give_the_serial_results(tmp_path: Path) -> None:
    """xacro keeps its file stack and includes in module globals: a failing expansion in one
    thread must neither reset them under another's nor take its location from another's."""
    from xrdf_tools.robot.xacro_source import expand_xacro
    from xrdf_tools.util.errors import XrdfToolsError

    (tmp_path / "part.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:macro name="box_link" params="name"><link name="${name}"><collision><geometry>'
        '<box size="0.1 0.1 0.1"/></geometry></collision></link></xacro:macro></robot>'
    )
    links = "".join(f'<xacro:box_link name="l{i}"/>' for i in range(40))
    good = tmp_path / "good.urdf.xacro"
    good.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        f'<xacro:include filename="part.xacro"/>{links}</robot>'
    )
    bad = tmp_path / "bad.urdf.xacro"
    bad.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:include filename="part.xacro"/>\n<xacro:box_link name="${no_such_name}"/>\n'
        "</robot>\n"
    )

    def expand(path: Path) -> str:
        try:
            return expand_xacro(path)
        except XrdfToolsError as e:
            return f"error: {e}"

    serial = {path: expand(path) for path in (good, bad)}
    assert serial[bad].startswith(f"error: {bad}:3")
    switch = sys.getswitchinterval()
    sys.setswitchinterval(1e-5)  # threads take turns often: an unguarded global shows
    try:
        with ThreadPoolExecutor(max_workers=2) as pool:
            results = list(pool.map(expand, [good, bad] * 100))
    finally:
        sys.setswitchinterval(switch)
    assert results == [serial[good], serial[bad]] * 100
