"""Which ``<material>`` elements of a COLLADA document pycollada loads.

Materials play no part in a mesh's shape, but a geometry instance that binds a material
pycollada could not load (its ``<effect>`` names a missing surface, say) is dropped with its
geometry, so trimesh reads no triangles there. :func:`loadable_materials` gives the ids of the
materials that surely load: an ``<effect>`` of ``profile_COMMON`` whose parameters (surfaces,
samplers) resolve and whose shading values are colours, numbers, textures or parameters, as
pycollada's ``Effect.load`` reads them. Anything else counts as not loaded, so the reader that
asks gives up rather than guess.
"""

from __future__ import annotations

from typing import Any

__all__ = ["loadable_materials"]

_SHADERS = ("phong", "lambert", "blinn", "constant")
_PROPERTIES = (
    "emission",
    "ambient",
    "diffuse",
    "specular",
    "shininess",
    "reflective",
    "reflectivity",
    "transparent",
    "transparency",
    "index_of_refraction",
)
_FLOAT_PARAMS = ("float", "float2", "float3", "float4")


def loadable_materials(root: Any, ns: str) -> set[str]:
    """The ids of the ``<material>`` elements of ``root`` (namespace ``ns``, ``{…}``) that
    pycollada loads."""
    images = {
        i.get("id")
        for lib in root.findall(f"{ns}library_images")
        for i in lib.findall(f"{ns}image")
        if i.find(f"{ns}init_from") is not None
    }
    effects = {
        e.get("id")
        for lib in root.findall(f"{ns}library_effects")
        for e in lib.findall(f"{ns}effect")
        if _effect_loads(e, ns, images)
    }
    out: set[str] = set()
    for lib in root.findall(f"{ns}library_materials"):
        for material in lib.findall(f"{ns}material"):
            instance = material.find(f"{ns}instance_effect")
            url = "" if instance is None else instance.get("url") or ""
            if material.get("id") and url.startswith("#") and url[1:] in effects:
                out.add(material.get("id"))
    return out


def _effect_loads(effect: Any, ns: str, images: set[str | None]) -> bool:
    profile = effect.find(f"{ns}profile_COMMON")
    if profile is None or profile.find(f"{ns}image") is not None:
        return False
    technique = profile.find(f"{ns}technique")
    if technique is None:
        return False
    scope: dict[str, str] = {}
    if not all(_params_load(parent, ns, images, scope) for parent in (profile, technique)):
        return False
    shading = next(
        (s for s in (technique.find(ns + name) for name in _SHADERS) if s is not None), None
    )
    if shading is None or effect.find(f".//{ns}extra//{ns}texture") is not None:
        return False
    return all(
        _value_loads(value, ns)
        for value in (shading.find(ns + name) for name in _PROPERTIES)
        if value is not None
    )


def _params_load(parent: Any, ns: str, images: set[str | None], scope: dict[str, str]) -> bool:
    """Whether each ``<newparam>`` of ``parent`` loads; surfaces and samplers go in ``scope``
    (sid: kind)."""
    for param in parent.findall(f"{ns}newparam"):
        sid = param.get("sid")
        surface, sampler = param.find(f"{ns}surface"), param.find(f"{ns}sampler2D")
        if surface is not None:
            init = surface.find(f"{ns}init_from")
            if not sid or surface.get("type") != "2D" or init is None:
                return False
            if init.text in scope or init.text not in images:
                return False
            scope[sid] = "surface"
        elif sampler is not None:
            source = sampler.find(f"{ns}source")
            if not sid or source is None or scope.get(source.text or "") != "surface":
                return False
            scope[sid] = "sampler"
        elif any(param.find(ns + kind) is not None for kind in _FLOAT_PARAMS):
            return False
    return True


def _value_loads(value: Any, ns: str) -> bool:
    children = list(value)
    if not children or not isinstance(children[0].tag, str):
        return False
    first, tag = children[0], children[0].tag
    try:
        if tag == f"{ns}color":
            [float(v) for v in first.text.split()]
        elif tag == f"{ns}float":
            float(first.text)
    except (AttributeError, TypeError, ValueError):
        return False
    return tag != f"{ns}texture" or first.get("texture") is not None
