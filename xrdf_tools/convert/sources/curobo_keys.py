"""What cuRobo's own loaders make of a key the conversion does not carry into the XRDF.

cuRobo builds its kinematics and c-space settings with ``Config(**mapping)`` (0.7.x:
``CudaRobotGeneratorConfig``, ``CSpaceConfig``; main: ``KinematicsLoaderCfg``,
``CSpaceParams``), so a key that neither version has is a ``TypeError`` there: the file does
not load. A key at the value cuRobo takes when it is absent (``null``, a scale of 1, a clip of 0)
changes nothing, and dropping it loses nothing.
"""

from __future__ import annotations

from typing import Any

__all__ = ["changes_nothing", "key_text", "unknown_to_curobo"]

#: ``kinematics`` keys of cuRobo 0.7.8 and of cuRobo main, together.
KINEMATICS_KEYS = frozenset(
    [
        "base_link",
        "ee_link",
        "tool_frames",
        "link_names",
        "collision_link_names",
        "collision_spheres",
        "collision_sphere_buffer",
        "compute_jacobian",
        "self_collision_buffer",
        "self_collision_ignore",
        "debug",
        "use_global_cumul",
        "asset_root_path",
        "mesh_link_names",
        "load_link_names_with_mesh",
        "grasp_contact_link_names",
        "load_tool_frames_with_mesh",
        "urdf_path",
        "usd_path",
        "usd_robot_root",
        "isaac_usd_path",
        "use_usd_kinematics",
        "usd_flip_joints",
        "usd_flip_joint_limits",
        "lock_joints",
        "extra_links",
        "add_object_link",
        "use_external_assets",
        "external_asset_path",
        "external_robot_configs_path",
        "extra_collision_spheres",
        "load_collision_spheres",
        "num_envs",
        "cspace",
        "load_meshes",
        "format_version",
    ]
)
#: ``cspace`` keys of cuRobo 0.7.8 and of cuRobo main, together.
CSPACE_KEYS = frozenset(
    [
        "joint_names",
        "retract_config",
        "default_joint_position",
        "cspace_distance_weight",
        "null_space_weight",
        "null_space_maximum_distance",
        "max_acceleration",
        "max_jerk",
        "velocity_scale",
        "acceleration_scale",
        "jerk_scale",
        "position_limit_clip",
    ]
)
#: The value cuRobo takes for an absent key, where it is not ``None``.
_DEFAULTS: dict[str, Any] = {
    "add_object_link": False,
    "load_tool_frames_with_mesh": False,
    "load_link_names_with_mesh": False,
    "compute_jacobian": False,
    "load_collision_spheres": True,
    "num_envs": 1,
    "velocity_scale": 1.0,
    "acceleration_scale": 1.0,
    "jerk_scale": 1.0,
    "position_limit_clip": 0.0,
}


def key_text(key: Any) -> str:
    """A mapping key as the file spells it: ``null``, ``true``, ``5`` (not Python's ``None``,
    ``True``)."""
    if key is None:
        return "null"
    return str(key).lower() if isinstance(key, bool) else str(key)


def unknown_to_curobo(key: str, section: str) -> bool:
    """``key`` is in neither cuRobo version's ``kinematics`` (or ``cspace``) settings."""
    known = CSPACE_KEYS if section == "cspace" else KINEMATICS_KEYS
    return str(key) not in known


def changes_nothing(key: str, value: Any) -> bool:
    """``value`` is what cuRobo takes when ``key`` is absent: null, an empty mapping or list,
    or the default (a scale of 1, a clip of 0), alone or once per joint."""
    if value is None or value == {} or value == []:
        return True
    default = _DEFAULTS.get(str(key))
    if default is None:
        return False
    values = value if isinstance(value, list) else [value]
    return all(_same(v, default) for v in values)


def _same(value: Any, default: Any) -> bool:
    """Equal, and a boolean only to a boolean (``0`` is not ``False`` here)."""
    return isinstance(value, bool) == isinstance(default, bool) and bool(value == default)
