"""Sheets: solids far thinner than they are wide, and thinner than the protrusion bound.

A marker plate, a sticker, a sheet-metal cover fitted as its bounding box: any sphere over a
sheet of thickness ``t`` protrudes by about its own radius, so the default count (the fewest
spheres covering ``target_coverage`` of the volume within the protrusion bound ``tau``) would
need about ``area / (pi (tau^2 + t tau))`` spheres -- hundreds for a 60 mm plate at a 2 mm
bound -- and stops at its cap with most of the plate bare. Volume coverage is the wrong
yardstick there; what a planner needs is the whole area inside few spheres.

A solid is a **sheet** when its oriented bounding box's smallest extent ``t`` (its thickness)
is at most ``1 / SHEET_ASPECT`` of the middle extent ``b`` (its width) and at most the
protrusion bound ``tau``: a sphere within the bound is then wider than the sheet is thick, so
the bound cannot be what limits the spheres. (A part that is flat even as a hull becomes a
box ``MIN_THICKNESS`` thick, which equals the smallest default bound: a sheet too.)

Without a count and without a bound of its own, a sheet gets two rows of spheres along its
length ``a``: its box cut into square cells half its width ``b`` wide (``ceil(2a / b)`` along
the length, at most ``SHEET_MAX_SPHERES`` in all, the cells lengthening for a long strip), each
cell inside the smallest sphere containing it. So the whole sheet lies inside the spheres, and
each reaches about a third of the sheet's width from its faces (``b / (2√2)``): a sphere per
sheet would reach 0.7 of its width (43 mm over a 60 mm marker plate), more than the link it
sits on. A big sheet's two rows would reach as far (a mobile base's top plate: 0.25 m), so
when they would reach past ``SHEET_MAX_REACH`` the box is cut into the fewest square cells
whose spheres reach at most that, at most ``SHEET_MAX_CELLS`` (else the finest grid of that
many). With a bound of the link's own (and no count), the sheet's box is cut into the fewest
square cells whose spheres reach at most that bound past its faces, at most
``SHEET_MAX_CELLS_BOUND`` (else the finest grid of that many, said as reaching past the bound).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..util.arrays import FloatArray
from ..xrdf.model import Sphere
from .obb import oriented_box

if TYPE_CHECKING:
    import trimesh

#: A sheet's thickness is at most this fraction's inverse of its width.
SHEET_ASPECT = 10.0
#: The most spheres a sheet gets by default, while they reach at most ``SHEET_MAX_REACH``.
SHEET_MAX_SPHERES = 16
#: How far past its faces the default spheres of a sheet may reach (metres): about an arm
#: link's sphere. A bigger sheet (a mobile base's top plate) gets finer cells.
SHEET_MAX_REACH = 0.05
#: The most cells a sheet is cut into to keep its spheres within the default reach; past it
#: the finest grid of this many is taken.
SHEET_MAX_CELLS = 64
#: The same under a protrusion bound the user gave for the sheet.
SHEET_MAX_CELLS_BOUND = 256
#: Cells across a sheet's width by default (square cells along its length).
_ACROSS = 2
#: Relative slack when the thickness is compared with the bound (a box made exactly as thick
#: as the smallest bound must count as a sheet whatever the round-off of its bounding box).
_BOUND_SLACK = 1e-6
#: A length within this share of a whole number of widths counts as that many (a square
#: plate measured 60.0 by 59.9 mm gets one sphere, not two).
_SQUARE_SLACK = 0.01
#: Centres are written to 0.1 mm: each radius grows by the farthest a rounded centre moves.
_CENTRE_ROUNDING = math.sqrt(3.0) * 0.5e-4


@dataclass(frozen=True)
class Sheet:
    """A sheet's oriented bounding box: ``thickness <= width <= length`` (metres) and the
    transform from the box's frame (axes in that order, centred) to the link frame."""

    thickness: float
    width: float
    length: float
    to_link: FloatArray

    @property
    def cells(self) -> tuple[int, int]:
        """Cells along the length and the width by default: :data:`_ACROSS` across, square
        ones along (within ``_SQUARE_SLACK``), at most ``SHEET_MAX_SPHERES`` in all; when
        their spheres would reach past ``SHEET_MAX_REACH``, the fewest square cells within
        it (at most ``SHEET_MAX_CELLS``, else the finest grid of that many)."""
        along = math.ceil(_ACROSS * self.length / self.width - _SQUARE_SLACK)
        shape = max(1, min(SHEET_MAX_SPHERES // _ACROSS, along)), _ACROSS
        if self.reach(shape) <= SHEET_MAX_REACH:
            return shape
        return self.grid_within(SHEET_MAX_REACH, SHEET_MAX_CELLS) or self.finest_grid()

    def reach(self, shape: tuple[int, int]) -> float:
        """How far past the faces the spheres of ``shape`` cells reach (before rounding)."""
        da, db = self.length / shape[0], self.width / shape[1]
        return 0.5 * math.sqrt(da**2 + db**2 + self.thickness**2) - self.thickness / 2.0

    def finest_grid(self, most: int = SHEET_MAX_CELLS) -> tuple[int, int]:
        """The square cells of the smallest side that number at most ``most``."""
        side = math.sqrt(self.length * self.width / most)
        while True:
            shape = (
                max(1, math.ceil(self.length / side - 1e-9)),
                max(1, math.ceil(self.width / side - 1e-9)),
            )
            if shape[0] * shape[1] <= most:
                return shape
            side *= 1.01

    def grid_within(self, bound: float, most: int) -> tuple[int, int] | None:
        """Cells along the length and the width: the fewest square ones whose spheres reach
        at most ``bound`` past the faces (after rounding), or None when that takes more than
        ``most``."""
        half = self.thickness / 2.0
        reach = bound - 2.0 * _CENTRE_ROUNDING - 1e-4  # what rounding a radius up may add
        if reach <= 0.0:
            return None
        side = math.sqrt(2.0) * math.sqrt((reach + half) ** 2 - half**2)
        shape = (
            max(1, math.ceil(self.length / side - 1e-9)),
            max(1, math.ceil(self.width / side - 1e-9)),
        )
        return shape if shape[0] * shape[1] <= most else None


def as_sheet(solid: trimesh.Trimesh, bound: float) -> Sheet | None:
    """The sheet ``solid`` is under the protrusion bound ``bound``, or None when it is not one
    (see the module docstring)."""

    volume, area = float(abs(solid.volume)), float(solid.area)
    # twice the volume over the area is at most the thickness of any solid lying in a slab
    # (the area is at least twice the slab-projected area, the volume at most that times the
    # thickness): a cheap test that rules out every solid but a thin one
    if area <= 0.0 or 2.0 * volume / area > bound * (1.0 + _BOUND_SLACK):
        return None
    sheet = as_plate(solid)
    if sheet is None or sheet.thickness > bound * (1.0 + _BOUND_SLACK):
        return None
    return sheet


def as_plate(solid: trimesh.Trimesh) -> Sheet | None:
    """``solid`` as a sheet whatever its protrusion bound: its oriented box's thickness is at
    most ``1 / SHEET_ASPECT`` of its width (a table top 20 mm thick under a 15.8 mm bound), or
    None."""
    try:
        to_link, extents = oriented_box(solid.vertices)
    except Exception:  # qhull fails on a solid below its tolerances (a part scaled to 0.1 µm)
        return None
    t, b, a = (float(e) for e in extents)
    return Sheet(t, b, a, to_link) if t <= b / SHEET_ASPECT else None


def face_reach(sheet: Sheet, spheres: tuple[Sphere, ...]) -> float:
    """How far ``spheres`` reach past the faces of ``sheet`` (metres, 0 for none): across its
    thickness, the farthest a sphere's surface lies from its mid-plane, less half the
    thickness."""
    if not spheres:
        return 0.0
    normal, middle = sheet.to_link[:3, 0], sheet.to_link[:3, 3]
    centres = np.array([s.center for s in spheres], dtype=np.float64)
    radii = np.array([s.radius for s in spheres], dtype=np.float64)
    across = np.abs((centres - middle) @ normal) + radii
    return float(across.max()) - sheet.thickness / 2.0


#: A sheet and its cells along its length and width (None: its default :attr:`Sheet.cells`).
SheetPlan = tuple[Sheet, tuple[int, int] | None]


def sheet_plan(solid: trimesh.Trimesh, own: float | None) -> SheetPlan | None:
    """How the sheet rule fits ``solid`` when it is a sheet: its default cells under the
    default bound (``own`` None), else the grid within the bound ``own`` (at most
    ``SHEET_MAX_CELLS_BOUND`` cells, else the finest grid of that many, which reaches past
    the bound: :func:`sheet_message` says so); None when the rule does not apply. A fit by volume
    is no fallback: on a sheet thinner than the distance grid's cells it places poor spheres."""
    from .fit import default_max_protrusion

    sheet = as_sheet(solid, default_max_protrusion(solid) if own is None else own)
    if sheet is None or own is None:
        return None if sheet is None else (sheet, None)
    most = SHEET_MAX_CELLS_BOUND
    return sheet, sheet.grid_within(own, most) or sheet.finest_grid(most)


def sheet_spheres(
    sheet: Sheet, shape: tuple[int, int] | None = None, solid: trimesh.Trimesh | None = None
) -> tuple[Sphere, ...]:
    """The sheet's spheres: its box cut into ``shape`` cells along its length and width
    (default: :attr:`Sheet.cells`), each inside the smallest sphere containing it (centres
    rounded to 0.1 mm, radii rounded up to 0.1 mm after growing by the farthest a rounded
    centre moves). With ``solid``, only the cells some of its triangles reach: two plates
    far apart in one mesh are one sheet's box, whose spheres filled the space between them
    (51 spheres along the 5 m between two 0.1 m plates)."""
    from .fit import _rounded

    n_a, n_b = sheet.cells if shape is None else shape
    da, db = sheet.length / n_a, sheet.width / n_b
    along = -sheet.length / 2.0 + da * (np.arange(n_a, dtype=np.float64) + 0.5)
    across = -sheet.width / 2.0 + db * (np.arange(n_b, dtype=np.float64) + 0.5)
    local = np.zeros((n_a * n_b, 4), dtype=np.float64)
    local[:, 2] = np.repeat(along, n_b)
    local[:, 1] = np.tile(across, n_a)
    local[:, 3] = 1.0
    if solid is not None:
        local = local[_reached_cells(sheet, (n_a, n_b), solid)]
    centres = np.einsum("ij,nj->ni", sheet.to_link, local)[:, :3]
    radius = 0.5 * math.sqrt(da**2 + db**2 + sheet.thickness**2) + _CENTRE_ROUNDING
    out = []
    for c in centres:
        s = _rounded(c, radius)
        x, y, z = (v + 0.0 for v in s.center)  # no -0.0
        out.append(Sphere(center=(x, y, z), radius=s.radius))
    return tuple(out)


def _reached_cells(sheet: Sheet, shape: tuple[int, int], solid: trimesh.Trimesh) -> np.ndarray:
    """Which of the sheet's cells (in :func:`sheet_spheres`' order, along-major) the box of
    some triangle of ``solid`` overlaps, in the sheet's plane: a superset of the cells that
    hold any of it, so their spheres still cover all of it. Every cell when the solid has no
    triangle. A 2D difference array over the cells: time linear in the triangles."""
    n_a, n_b = shape
    faces = np.asarray(solid.faces, dtype=np.int64)
    if len(faces) == 0:
        return np.ones(n_a * n_b, dtype=bool)
    to_sheet = np.linalg.inv(sheet.to_link)
    points = np.asarray(solid.vertices, dtype=np.float64) @ to_sheet[:3, :3].T + to_sheet[:3, 3]
    tri = points[faces]  # (F, 3, 3): columns 2 and 1 are along and across
    cells = []
    for axis, extent, n in ((2, sheet.length, n_a), (1, sheet.width, n_b)):
        size, slack = extent / n, 1e-9 * max(extent, 1e-9)
        low = np.floor((tri[:, :, axis].min(axis=1) - slack + extent / 2.0) / size)
        high = np.floor((tri[:, :, axis].max(axis=1) + slack + extent / 2.0) / size)
        first = np.clip(low, 0, n - 1).astype(np.int64)
        cells.append((first, np.clip(high, 0, n - 1).astype(np.int64) + 1))
    (a0, a1), (b0, b1) = cells
    marks = np.zeros((n_a + 1, n_b + 1), dtype=np.int64)
    for rows, cols, sign in ((a0, b0, 1), (a0, b1, -1), (a1, b0, -1), (a1, b1, 1)):
        np.add.at(marks, (rows, cols), sign)
    return (marks.cumsum(axis=0).cumsum(axis=1)[:n_a, :n_b] > 0).reshape(-1)


def sheet_message(
    link: str, sheet: Sheet, spheres: tuple[Sphere, ...], bound: float, own: bool
) -> tuple[str, bool]:
    """What was done to a sheet (``own``: under a protrusion bound given for it), and the
    options that change it; True when its spheres reach past that bound (a warning)."""
    mm = 1000.0
    radius = max(s.radius for s in spheres)
    reach = radius - sheet.thickness / 2.0
    size = f"{sheet.length * mm:.4g} × {sheet.width * mm:.4g} × {sheet.thickness * mm:.3g} mm"
    n = len(spheres)
    what = f"1 sphere of radius {radius * mm:.1f} mm covers" if n == 1 else ""
    what = what or f"{n} spheres of radius {radius * mm:.1f} mm cover"
    head = f"link '{link}' is a sheet ({size}, no thicker than its {bound * mm:.3g} mm protrusion "
    if own and reach > bound:
        return head + (
            f"bound, given): {what} all of it, reaching {reach * mm:.1f} mm, past the bound: "
            f"within it would take more than {SHEET_MAX_CELLS_BOUND} spheres; --per-link N "
            "fits N spheres to its volume"
        ), True
    if own:
        return head + f"bound, given): {what} all of it, reaching {reach * mm:.1f} mm", False
    return head + (
        f"bound): {what} all of it, reaching {reach * mm:.1f} mm from its faces; --per-link N "
        "fits N spheres to its volume, `xrdf spheres --max-protrusion M` covers it with "
        "spheres reaching at most M"
    ), False


def plate_message(
    link: str,
    plate: Sheet,
    spheres: tuple[Sphere, ...],
    bound: float,
    past: float,
    fitted: int,
    moved_by: str | None = None,
) -> tuple[str, bool]:
    """What was done to a plate thicker than its default bound whose ``fitted`` spheres,
    refined past the bound, reached ``past`` metres from its faces; True when the sheet's
    spheres still reach past ``SHEET_MAX_REACH`` (a warning). ``moved_by``: the joint that
    moves the plate (a carriage on a rail), which a world cuboid would not follow."""
    mm = 1000.0
    radius = max(s.radius for s in spheres)
    reach = face_reach(plate, spheres)
    size = f"{plate.length * mm:.4g} × {plate.width * mm:.4g} × {plate.thickness * mm:.3g} mm"
    return (
        f"link '{link}' is a plate ({size}), thicker than its {bound * mm:.3g} mm default "
        f"protrusion bound and too wide to cover within it: {fitted} spheres refined past the "
        f"bound would reach {past * mm:.0f} mm from its faces; {len(spheres)} spheres of radius "
        f"{radius * mm:.1f} mm cover all of it, reaching {reach * mm:.1f} mm. "
        + _plate_advice(moved_by)
    ), reach > SHEET_MAX_REACH


def _plate_advice(moved_by: str | None) -> str:
    """What to do about a plate's far-reaching spheres: a fixed table goes to the planner as a
    world cuboid; a plate that joint ``moved_by`` carries needs its spheres, which move with it."""
    volume = "--per-link N fits N spheres to its volume"
    if moved_by is not None:
        return (
            f"It moves with joint '{moved_by}', so it keeps these spheres (a world cuboid "
            f"would not follow it); {volume}"
        )
    return (
        "A table or plate the robot stands on is better given to the planner as a world "
        f"cuboid; {volume}"
    )
