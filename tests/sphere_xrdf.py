"""An XRDF text for a synthetic robot: a c-space, spheres per frame, an optional mask."""

from __future__ import annotations

#: ``{frame: [(x, y, z, radius), ...]}``
Spheres = dict[str, list[tuple[float, float, float, float]]]


def sphere_xrdf(
    cspace: list[str],
    spheres: Spheres,
    ignore: dict[str, list[str]] | None = None,
) -> str:
    """XRDF 1.0 text: ``cspace`` (limits 10 and 100), one geometry group ``body`` with
    ``spheres`` for world and self collision, and ``ignore`` as the self-collision mask."""
    n = len(cspace)
    lines = [
        "format: xrdf",
        "format_version: 1.0",
        "cspace:",
        f"  joint_names: [{', '.join(cspace)}]",
        f"  acceleration_limits: [{', '.join(['10.0'] * n)}]",
        f"  jerk_limits: [{', '.join(['100.0'] * n)}]",
        "collision:",
        "  geometry: body",
        "self_collision:",
        "  geometry: body",
    ]
    if ignore:
        lines.append("  ignore:")
        lines += [f"    {a}: [{', '.join(bs)}]" for a, bs in ignore.items()]
    lines += ["geometry:", "  body:", "    spheres:"]
    for frame, items in spheres.items():
        lines.append(f"      {frame}:")
        lines += [f"        - {{center: [{x}, {y}, {z}], radius: {r}}}" for x, y, z, r in items]
    return "\n".join(lines) + "\n"
