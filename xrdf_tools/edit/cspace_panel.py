"""The c-space panel of the ``xrdf edit`` page: which joints the planner moves, their
acceleration and jerk limits, and the tool frames.

A joint is picked from the joints the c-space can hold (:meth:`EditRobot.cspace_joint_choices`,
URDF order); **In c-space** takes it in at its place in URDF order (cuRobo fills default
positions in URDF order, so that order keeps them right) or leaves it out, and the limits
fields set its limits. A joint taken in gets the limits shown, which for a joint not in the
c-space are ``xrdf convert``'s defaults. A c-space not in URDF order (a file written so) is
said under the table, with a button that puts it in that order. The Pose panel's sliders
follow the c-space. The last joint is not left out, nor the last tool frame removed: the
document refuses both (:mod:`xrdf_tools.edit.robot_checks`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..convert.core import DEFAULT_ACCELERATION, DEFAULT_JERK
from .edits import SetCspace, SetToolFrames
from .markup import code
from .surface import PageSurface, from_browser
from .typed import TypedNumber

if TYPE_CHECKING:
    from ..xrdf.model import CSpace

__all__ = ["CspacePanel", "cspace_table", "tool_frames_text"]

#: The limits fields' range: above 0 (every reader refuses 0) and below the numbers a saved
#: file holds.
MIN_LIMIT = 1e-3
MAX_LIMIT = 1e6


#: Under the table of a c-space not in URDF order.
UNORDERED = (
    "\n\n**Not in URDF order**: cuRobo fills default positions in URDF order, so joints "
    "whose defaults differ would start at each other's (`xrdf lint --target curobo` names "
    "them: curobo-default-order). **Put in URDF order** fixes it."
)


def cspace_table(cspace: CSpace | None) -> str:
    """The c-space as a markdown table (joint, acceleration, jerk), in its order."""
    if cspace is None or not cspace.joint_names:
        return "No c-space joints."
    rows = [
        f"| {code(n)} | {a:g} | {j:g} |"
        for n, a, j in zip(
            cspace.joint_names, cspace.acceleration_limits, cspace.jerk_limits, strict=True
        )
    ]
    head = f"{len(rows)} joint(s), in the order planners use:\n\n"
    return head + "| joint | acceleration | jerk |\n|---|---:|---:|\n" + "\n".join(rows)


def tool_frames_text(tools: tuple[str, ...] | list[str]) -> str:
    """The tool frames in order, the first marked as the end effector."""
    if not tools:
        return "No tool frames: cuRobo and cuMotion need one (the end effector)."
    rest = "".join(f", {code(f)}" for f in tools[1:])
    return f"Tool frames: {code(tools[0])} (end effector){rest}"


class CspacePanel:
    """Joint picker, membership toggle, limits and tool frames."""

    def __init__(self, page: PageSurface, gui: Any) -> None:
        self.page = page
        choices = page.robot.cspace_joint_choices() or ("(none)",)
        frames = page.robot.frame_names
        with gui.add_folder("C-space", expand_by_default=False):
            self.table = gui.add_markdown("")
            self.joint = gui.add_dropdown("Joint", choices, initial_value=choices[0])
            self.member = gui.add_checkbox(
                "In c-space",
                False,
                hint="Planned joints; one left out is held at its default position",
            )
            self.acceleration = TypedNumber(
                gui,
                "Acceleration limit",
                DEFAULT_ACCELERATION,
                lo=MIN_LIMIT,
                hi=MAX_LIMIT,
                hint="rad/s² (m/s² for a prismatic joint)",
            )
            self.jerk = TypedNumber(
                gui,
                "Jerk limit",
                DEFAULT_JERK,
                lo=MIN_LIMIT,
                hi=MAX_LIMIT,
                hint="rad/s³ (m/s³ for a prismatic joint); 1e3 is 1000",
            )
            self.order = gui.add_button(
                "Put in URDF order",
                visible=False,
                hint="cuRobo fills default positions in URDF order: keep the c-space in it",
            )
            self.tools = gui.add_markdown("")
            self.frame = gui.add_dropdown("Frame", frames, initial_value=frames[-1])
            add = gui.add_button("Add tool frame")
            remove = gui.add_button("Remove tool frame")
            end = gui.add_button(
                "Make end effector",
                hint="The first tool frame: cuRobo's ee_link, the frame a goal pose is for",
            )
        self.joint.on_update(lambda e: self.sync() if from_browser(e) else None)
        self.member.on_update(lambda e: self._set_member() if from_browser(e) else None)
        for field in (self.acceleration, self.jerk):
            field.on_number(page.say, lambda _: self._set_limits())
        self.order.on_click(lambda e: self._urdf_order() if from_browser(e) else None)
        add.on_click(lambda e: self._tool_frames(add=True) if from_browser(e) else None)
        remove.on_click(lambda e: self._tool_frames(add=False) if from_browser(e) else None)
        end.on_click(lambda e: self._tool_frames(add=True, first=True) if from_browser(e) else None)
        self.sync()

    # --- edits -----------------------------------------------------------------------------
    def _limits(self) -> tuple[float, float] | None:
        """The limits typed, None (said) when a field holds no number in its range."""
        values: list[float] = []
        for field in (self.acceleration, self.jerk):
            value = field.read()
            why = f"not set: type a number for {field.label}" if value is None else None
            if value is not None:
                why = field.refusal(value)
                values.append(value)
            if why is not None:
                self.page.say(why)
                return None
        return values[0], values[1]

    def _set_member(self) -> None:
        page = self.page
        joint = str(self.joint.value)
        if joint not in page.robot.cspace_joint_choices():
            page.say("this robot has no joint the c-space can hold")
            self.sync()
            return
        included = bool(self.member.value)
        limits = self._limits()
        if limits is None:
            self.sync()
            return
        acceleration, jerk = limits
        with page.lock:
            cspace = page.robot.cspace_with(
                page.state.xrdf, joint, included=included, acceleration=acceleration, jerk=jerk
            )
            verb = "take" if included else "leave"
            done = page.apply(
                SetCspace(cspace, f"{verb} {joint} {'into' if included else 'out of'} the c-space")
            )
            if done and included and not page.robot.moves_curobo_frames(page.state.xrdf, joint):
                page.say(
                    f"done: took {joint} into the c-space, but it moves no tool frame, sphere "
                    "frame or added frame: cuRobo builds its robot from those and would refuse "
                    "it (add a tool frame or spheres below it)"
                )
            self.sync()

    def _set_limits(self) -> None:
        page = self.page
        joint = str(self.joint.value)
        with page.lock:
            cs = page.state.xrdf.cspace
            if cs is None or joint not in cs.joint_names:
                page.say(
                    f"{joint} is not in the c-space: it gets these limits when taken in "
                    "(tick In c-space)"
                )
                return
            limits = self._limits()
            if limits is None:
                return
            acceleration, jerk = limits
            cspace = page.robot.cspace_with(
                page.state.xrdf, joint, included=True, acceleration=acceleration, jerk=jerk
            )
            page.apply(
                SetCspace(cspace, f"limits of {joint} to {acceleration:g}, {jerk:g}"),
                merge_key=("limits", joint),
            )

    def _urdf_order(self) -> None:
        page = self.page
        with page.lock:
            ordered = page.robot.urdf_ordered(page.state.xrdf)
            if ordered is None:
                page.say("no change: the c-space is in URDF order already")
            else:
                page.apply(SetCspace(ordered, "put the c-space in URDF order"))
            self.sync()

    def _tool_frames(self, *, add: bool, first: bool = False) -> None:
        """Add the picked frame (at the end, or ``first``: the end effector) or remove it.
        The last tool frame is not removed: cuRobo and cuMotion take the first as the end
        effector and refuse a file without one."""
        page = self.page
        frame = str(self.frame.value)
        with page.lock:
            now = tuple(page.state.xrdf.tool_frames or ())
            if first:
                frames = (frame, *(f for f in now if f != frame))
            elif add:
                frames = now if frame in now else (*now, frame)
            else:
                frames = tuple(f for f in now if f != frame)  # not the last: the document's check
            label = f"make {frame} the end effector (first tool frame)" if first else ""
            page.apply(SetToolFrames(frames, label))

    # --- showing the document --------------------------------------------------------------
    def sync(self) -> None:
        """Show the document's c-space and tool frames, and the picked joint's values."""
        x = self.page.state.xrdf
        unordered = self.page.robot.urdf_ordered(x) is not None
        self.table.content = cspace_table(x.cspace) + (UNORDERED if unordered else "")
        self.order.visible = unordered
        joint = str(self.joint.value)
        names = x.cspace.joint_names if x.cspace is not None else ()
        self.member.value = joint in names
        if x.cspace is not None and joint in names:
            k = names.index(joint)
            self.acceleration.show(float(x.cspace.acceleration_limits[k]))
            self.jerk.show(float(x.cspace.jerk_limits[k]))
        else:
            self.acceleration.show(DEFAULT_ACCELERATION)
            self.jerk.show(DEFAULT_JERK)
        tools = x.tool_frames or ()
        self.tools.content = tool_frames_text(tools)
