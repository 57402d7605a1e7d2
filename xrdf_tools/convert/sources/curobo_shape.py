"""The structure of a cuRobo robot YAML (classic and 2.0 layouts) or a Lula robot description,
checked once where the file is read (:func:`xrdf_tools.yaml.shape.check_shape`).

Only the containers are pinned down here: which keys hold a list of names, a mapping, a list.
Values (numbers, lengths, link names) are judged by :mod:`xrdf_tools.convert.sources.curobo`, which
reports them with their own messages; keys not listed are reported there as dropped.
"""

from __future__ import annotations

from ...yaml.shape import ANY, SCALAR, list_of, map_of, one_of

__all__ = ["CUROBO_FILE"]

NAMES = list_of(SCALAR, what="a list of names")
_EXTRA_LINK = map_of(
    None,
    fields={
        "parent_link_name": SCALAR,
        "link_name": SCALAR,
        "joint_name": SCALAR,
        "joint_type": SCALAR,
        "fixed_transform": list_of(ANY),
        "child_link_name": SCALAR,
    },
)
_BUFFER = one_of(SCALAR, map_of(ANY), what="a number or a mapping of link → number")
_CSPACE = map_of(
    None,
    fields={
        "joint_names": NAMES,
        "retract_config": list_of(ANY),
        "default_joint_position": list_of(ANY),
        "max_acceleration": one_of(SCALAR, list_of(ANY), what="a number or a list of numbers"),
        "max_jerk": one_of(SCALAR, list_of(ANY), what="a number or a list of numbers"),
    },
)
_KINEMATICS = map_of(
    None,
    fields={
        "base_link": SCALAR,
        "ee_link": SCALAR,
        "link_names": NAMES,
        "tool_frames": one_of(SCALAR, NAMES, what="a name or a list of names"),
        "collision_link_names": NAMES,
        "collision_spheres": one_of(
            SCALAR, map_of(ANY), what="a spheres file path or a mapping of link → spheres"
        ),
        "collision_sphere_buffer": _BUFFER,
        "self_collision_buffer": _BUFFER,
        "self_collision_ignore": map_of(NAMES, what="a mapping of link → [links]"),
        "extra_links": map_of(_EXTRA_LINK),
        "extra_collision_spheres": map_of(ANY),
        "lock_joints": map_of(ANY),
        "cspace": _CSPACE,
    },
)
#: A cuRobo config (``robot_cfg.kinematics`` or a bare ``kinematics``) or a Lula description
#: (top-level ``cspace`` list); the two share no top-level key.
CUROBO_FILE = map_of(
    None,
    fields={
        "robot_cfg": map_of(None, fields={"kinematics": _KINEMATICS}),
        "kinematics": _KINEMATICS,
        "cspace": NAMES,
        "cspace_to_urdf_rules": list_of(ANY),
        "collision_spheres": list_of(ANY),
        "default_q": list_of(ANY),
        "acceleration_limits": list_of(ANY),
        "jerk_limits": list_of(ANY),
    },
    what="a mapping (a cuRobo robot configuration or a Lula robot description)",
)
