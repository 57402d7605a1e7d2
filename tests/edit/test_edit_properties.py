"""The editor's document under any sequence of edits: a stateful property test.

A hypothesis state machine makes what the page of ``xrdf edit`` can send -- every edit kind,
with values a user can type or drag, edge ones included (0, negative, huge, NaN, infinite,
1e-320, names not in the robot, indexes out of range, the last sphere of a link, the last
tool frame, the last c-space joint) -- plus undo, redo and save, on real robots: the Panda
fixture and the UR10e fixture (XRDF 2.0, the UR10e with a ``set_base_frame`` modifier and a
world-collision group) and the one-command draft of the demo arm (XRDF 1.0, fitted spheres).
After every step:

* an edit is made or refused with :class:`EditError` (what the page shows as "not done"):
  no other exception escapes;
* undo then redo gives the same document;
* the document dumps canonically (``dump(parse(dump(x))) == dump(x)``) and ``xrdf lint``
  with the URDF finds no ERROR (edits may cause warnings: a sphere moved far from its link,
  a link left without spheres, a c-space not in URDF order, a pose in self-collision);
* a save writes exactly the dump, atomically (no file left beside it), and loads back equal;
* :class:`EditRobot` follows the c-space, poses at random and counts collisions.

Real inputs: example-robot-data's Panda URDF, fixtures/ur10e, fixtures/demo_arm.
"""

from __future__ import annotations

import math
import tempfile
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, event, settings
from hypothesis import strategies as st
from hypothesis.stateful import (
    RuleBasedStateMachine,
    initialize,
    invariant,
    precondition,
    rule,
    run_state_machine_as_test,
)

from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.edit import (
    AddSphere,
    ConnectSpheres,
    DeleteSphere,
    DuplicateSphere,
    Edit,
    EditError,
    EditRobot,
    EditState,
    MoveSphere,
    ScaleSpheres,
    SetBuffer,
    SetCspace,
    SetDefaults,
    SetIgnored,
    SetMask,
    SetRadius,
    SetToolFrames,
    save,
)
from xrdf_tools.lint import lint_text
from xrdf_tools.robot.binding import cspace_joints
from xrdf_tools.robot.core import Robot
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.xrdf.io import dump_xrdf, load_xrdf, parse_xrdf
from xrdf_tools.xrdf.model import Sphere, Xrdf

#: A name no robot has.
UNKNOWN = "no_such_name"

#: Numbers a user can type or a script can pass, the edge ones first.
EDGE = (0.0, -0.0, 1e-320, -1e-320, 1e-7, -1.0, 1e6, -1e6, 1.0000001e6, 1e12, 1e300)
EDGE += (math.nan, math.inf, -math.inf)
numbers = st.one_of(
    st.sampled_from(EDGE), st.floats(-2.0, 2.0, allow_nan=False), st.floats(1e-4, 0.3)
)
centers = st.tuples(numbers, numbers, numbers)
#: Indexes past any list (negative ones too: not counted from the end).
far_indexes = st.sampled_from((-1, -2, 10**6, 2**63))


@dataclass(frozen=True)
class Document:
    """A robot and the XRDF the editor starts from."""

    robot: Robot
    xrdf: Xrdf


@cache
def document(name: str) -> Document:
    if name == "panda":
        return Document(
            load_robot(robot_urdf("panda")), load_xrdf(FIXTURES / "panda" / "panda.xrdf")
        )
    if name == "ur10e":
        ur10e = FIXTURES / "ur10e"
        return Document(load_robot(ur10e / "ur10e.urdf"), load_xrdf(ur10e / "ur10e.xrdf"))
    from xrdf_tools.convert.core import ConvertOptions
    from xrdf_tools.convert.pipeline import FitOptions, MaskOptions, convert_robot

    demo = FIXTURES / "demo_arm"
    robot = load_robot(demo / "demo_arm.urdf")
    draft = convert_robot(  # as `xrdf edit --urdf demo_arm.urdf --srdf ... -o` starts from,
        robot,  # with fewer spheres and samples to stay fast
        ConvertOptions(srdf=demo / "demo_arm.srdf"),
        fit=FitOptions(seed=0, per_link=4),
        mask=MaskOptions(samples=500, seed=0),
        lint=False,
    )
    return Document(robot, draft.xrdf)


def lint_errors(text: str, robot: Robot) -> list[str]:
    return [
        f"{d.rule}: {d.message}"
        for d in lint_text(text, "edited.xrdf", urdf_model=robot)
        if d.severity.name == "ERROR"
    ]


class Editor(RuleBasedStateMachine):
    """Edits of one document; :func:`editor_machine` names the document."""

    doc: Document
    tmp: Path
    frames: tuple[str, ...]  # the robot's, then one it does not have
    sphere_frames: tuple[str, ...]  # the frames with spheres in the starting document
    joints: tuple[str, ...]  # every URDF joint, then one the robot does not have
    choices: tuple[str, ...]  # the joints the c-space can hold
    baseline: frozenset[str]  # lint's errors on the starting document (none, so far)

    state: EditState
    robot: EditRobot
    linted: str

    @initialize()
    def start(self) -> None:
        self.robot = EditRobot(self.doc.robot, self.doc.xrdf)
        self.state = EditState.start(self.doc.xrdf, robot=self.robot)
        self.linted = ""

    # --- what a user picks -----------------------------------------------------------------
    def frame(self, data: st.DataObject) -> str:
        mostly_with_spheres = st.one_of(
            st.sampled_from(self.sphere_frames), st.sampled_from(self.frames)
        )
        return data.draw(mostly_with_spheres, label="frame")

    def joint(self, data: st.DataObject) -> str:
        either = st.one_of(st.sampled_from(self.choices), st.sampled_from(self.joints))
        return data.draw(either, label="joint")

    def index(self, data: st.DataObject, frame: str) -> int:
        n = len(self.state.xrdf.resolved_spheres(self.state.group).get(frame, ()))
        inside = st.integers(0, n - 1) if n else st.just(0)
        return data.draw(st.one_of(inside, inside, inside, st.just(n), far_indexes), label="index")

    # --- how an edit is made ---------------------------------------------------------------
    def make(self, edit: Edit, merge_key: Any = None) -> bool:
        """Apply ``edit`` as the page does; a refusal is an :class:`EditError` of one line
        and leaves the state as it was. Undo then redo of a made edit is the same document."""
        before = self.state
        try:
            new = before.apply(edit, merge_key=merge_key)
        except EditError as e:
            assert str(e) and "\n" not in str(e), repr(e)
            event(f"{type(edit).__name__}: refused")
            return False
        if new is before:
            event(f"{type(edit).__name__}: no change")
            return False
        event(f"{type(edit).__name__}: made")
        assert new.undo().redo().xrdf == new.xrdf
        if merge_key is None or merge_key != before.merge_key:
            assert new.undo().xrdf is before.xrdf
        self.state = new
        self.robot.follow(new.xrdf)
        return True

    # --- spheres ---------------------------------------------------------------------------
    @rule(data=st.data(), center=centers, drag=st.booleans())
    def move_sphere(self, data: st.DataObject, center: Any, drag: bool) -> None:
        frame = self.frame(data)
        k = self.index(data, frame)
        self.make(MoveSphere(frame, k, center), ("move", frame, k) if drag else None)

    @rule(data=st.data(), radius=numbers)
    def set_radius(self, data: st.DataObject, radius: float) -> None:
        frame = self.frame(data)
        k = self.index(data, frame)
        self.make(SetRadius(frame, k, radius), ("radius", frame, k))

    @rule(data=st.data(), center=centers, radius=numbers)
    def add_sphere(self, data: st.DataObject, center: Any, radius: float) -> None:
        self.make(AddSphere(self.frame(data), Sphere(center, radius)))

    @rule(data=st.data())
    def duplicate_sphere(self, data: st.DataObject) -> None:
        frame = self.frame(data)
        self.make(DuplicateSphere(frame, self.index(data, frame)))

    @rule(data=st.data())
    def delete_sphere(self, data: st.DataObject) -> None:
        frame = self.frame(data)
        self.make(DeleteSphere(frame, self.index(data, frame)))

    @rule(data=st.data())
    def delete_every_sphere_of_a_link(self, data: st.DataObject) -> None:
        """Down to the last sphere of the link, and that one too."""
        frame = self.frame(data)
        while self.make(DeleteSphere(frame, 0)):
            pass

    @rule(data=st.data(), count=st.integers(-1, 40))
    def connect_spheres(self, data: st.DataObject, count: int) -> None:
        frame = self.frame(data)
        first, second = self.index(data, frame), self.index(data, frame)
        self.make(ConnectSpheres(frame, first, second, count))

    @rule(data=st.data(), factor=numbers)
    def scale_spheres(self, data: st.DataObject, factor: float) -> None:
        self.make(ScaleSpheres(self.frame(data), factor))

    # --- the mask and buffers --------------------------------------------------------------
    @rule(data=st.data(), ignored=st.booleans())
    def set_ignored(self, data: st.DataObject, ignored: bool) -> None:
        self.make(SetIgnored(self.frame(data), self.frame(data), ignored))

    @rule(data=st.data())
    def set_mask(self, data: st.DataObject) -> None:
        """A report's recommendation: pairs of two of the robot's frames."""
        robot_frames = st.sampled_from(self.frames[:-1])
        pairs = data.draw(st.lists(st.tuples(robot_frames, robot_frames)), label="pairs")
        ignore: dict[str, list[str]] = {}
        for a, b in pairs:
            if a != b and b not in ignore.get(a, ()) and a not in ignore.get(b, ()):
                ignore.setdefault(a, []).append(b)
        self.make(SetMask({a: tuple(bs) for a, bs in ignore.items()}))

    @rule(data=st.data(), distance=numbers)
    def set_buffer(self, data: st.DataObject, distance: float) -> None:
        frame = self.frame(data)
        self.make(SetBuffer(frame, distance), ("buffer", frame))

    # --- default positions -----------------------------------------------------------------
    @rule(seed=st.integers(0, 2**32 - 1))
    def use_pose_as_default(self, seed: int) -> None:
        q = self.robot.random_pose(self.state.xrdf, seed)
        self.make(SetDefaults(self.robot.cspace_values(q)))

    @rule(data=st.data(), value=numbers)
    def set_default(self, data: st.DataObject, value: float) -> None:
        self.make(SetDefaults({self.joint(data): value}))

    # --- the c-space and tool frames -------------------------------------------------------
    @rule(data=st.data(), included=st.booleans(), acceleration=numbers, jerk=numbers)
    def cspace_member(
        self, data: st.DataObject, included: bool, acceleration: float, jerk: float
    ) -> None:
        cspace = self.robot.cspace_with(
            self.state.xrdf,
            self.joint(data),
            included=included,
            acceleration=acceleration,
            jerk=jerk,
        )
        self.make(SetCspace(cspace))

    @rule()
    def leave_out_every_cspace_joint(self) -> None:
        """Down to the last c-space joint, and that one too."""
        cs = self.state.xrdf.cspace
        for joint in cs.joint_names if cs is not None else ():
            x = self.state.xrdf
            self.make(
                SetCspace(self.robot.cspace_with(x, joint, included=False, acceleration=1, jerk=1))
            )

    @rule()
    def put_cspace_in_urdf_order(self) -> None:
        ordered = self.robot.urdf_ordered(self.state.xrdf)
        if ordered is not None:
            self.make(SetCspace(ordered))

    @rule(data=st.data(), how=st.sampled_from(("add", "remove", "first", "none")))
    def tool_frames(self, data: st.DataObject, how: str) -> None:
        """As the page's buttons: add a frame at the end, remove one (the last one too), make
        one the end effector; or none at all."""
        frame = self.frame(data)
        now = tuple(self.state.xrdf.tool_frames or ())
        if how == "first":
            frames = (frame, *(f for f in now if f != frame))
        elif how == "add":
            frames = now if frame in now else (*now, frame)
        elif how == "remove":
            frames = tuple(f for f in now if f != frame)
        else:
            frames = ()
        self.make(SetToolFrames(frames))

    # --- history and saving ----------------------------------------------------------------
    @precondition(lambda self: self.state.can_undo)
    @rule()
    def undo(self) -> None:
        before = self.state
        self.state = before.undo()
        assert self.state.redo().xrdf == before.xrdf
        self.robot.follow(self.state.xrdf)

    @precondition(lambda self: self.state.can_redo)
    @rule()
    def redo(self) -> None:
        before = self.state
        self.state = before.redo()
        assert self.state.undo().xrdf == before.xrdf
        self.robot.follow(self.state.xrdf)

    @rule()
    def undo_everything_then_redo_everything(self) -> None:
        """Back to the document the editor started from, and forward to this one again."""
        now, n = self.state, len(self.state.undo_stack)
        first = now
        for _ in range(n):
            first = first.undo()
        assert first.xrdf == self.doc.xrdf and not first.can_undo
        last = first
        for _ in range(n):
            last = last.redo()
        assert last.xrdf == now.xrdf and last.redo_stack == now.redo_stack

    @rule()
    def save(self) -> None:
        """Over an existing file: exactly the dump, nothing left beside it, loads back."""
        folder = Path(tempfile.mkdtemp(dir=self.tmp))
        target = folder / "robot.xrdf"
        target.write_text("the file before the save\n")
        self.state = save(self.state, target)
        assert [p.name for p in folder.iterdir()] == ["robot.xrdf"]
        assert target.read_text(encoding="utf-8") == self.state.text()
        assert load_xrdf(target) == self.state.xrdf
        assert not self.state.dirty

    # --- after every step ------------------------------------------------------------------
    @invariant()
    def dumps_canonically_and_lints_clean(self) -> None:
        if not hasattr(self, "state"):
            return
        text = self.state.text()
        if text == self.linted:
            return
        assert dump_xrdf(parse_xrdf(text)) == text
        # a change below the diff's tolerance (a default of 1e-320 for 0) is unsaved all the same
        assert self.state.dirty or not self.state.diff().changes
        errors = set(lint_errors(text, self.doc.robot)) - self.baseline
        assert not errors, errors
        self.linted = text

    @invariant()
    def robot_poses_and_counts_collisions(self) -> None:
        if not hasattr(self, "state"):
            return
        x = self.state.xrdf
        assert self.robot.cspace == cspace_joints(self.robot.kin, x)  # all for an empty one
        q = self.robot.random_pose(x, seed=len(self.state.undo_stack))
        assert np.all(np.isfinite(q))
        assert np.all(self.robot.lower <= q[self.robot.cspace_index])
        assert np.all(q[self.robot.cspace_index] <= self.robot.upper)
        hits = self.robot.collisions(x, q)
        assert not any(c.masked for c in hits.checked)
        self.robot.collisions(x, self.robot.default_pose(x))


def editor_machine(doc: Document, tmp: Path) -> type[Editor]:
    """:class:`Editor` over ``doc``, saving into ``tmp``."""
    er = EditRobot(doc.robot, doc.xrdf)
    sphere_frames = {f for g in (doc.xrdf.geometry or {}).values() for f in g.spheres}
    facts = {
        "doc": doc,
        "tmp": tmp,
        "frames": (*er.frame_names, UNKNOWN),
        "sphere_frames": tuple(sorted(sphere_frames)),
        "joints": (*doc.robot.joints, UNKNOWN),
        "choices": er.cspace_joint_choices(),
        "baseline": frozenset(lint_errors(dump_xrdf(doc.xrdf), doc.robot)),
    }
    return type(f"Editor_{doc.robot.name}", (Editor,), facts)


def run_editor(name: str, tmp_path: Path, *, examples: int, steps: int) -> None:
    machine = editor_machine(document(name), tmp_path)
    run_state_machine_as_test(
        machine,
        settings=settings(
            max_examples=examples,
            stateful_step_count=steps,
            derandomize=True,
            deadline=None,
            database=None,
            suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
        ),
    )


DOCUMENTS = ("panda", "ur10e", "demo_arm_draft")


@pytest.mark.parametrize("name", DOCUMENTS)
def test_any_sequence_of_edits_keeps_the_document_whole(name: str, tmp_path: Path) -> None:
    run_editor(name, tmp_path, examples=8, steps=15)


@pytest.mark.slow
@pytest.mark.parametrize("name", DOCUMENTS)
def test_any_longer_sequence_of_edits_keeps_the_document_whole(name: str, tmp_path: Path) -> None:
    run_editor(name, tmp_path, examples=40, steps=25)
