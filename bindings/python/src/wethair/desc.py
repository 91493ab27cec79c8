"""Building a ``WetHairSimDesc`` from keywords: the library's defaults first, then only the
fields named. Field names are the header's; a nested struct takes a dict of its fields; an
enum field takes a member, its value or its name."""

from __future__ import annotations

import ctypes as C
from typing import Any, Mapping

from . import _structs as S
from ._lib import lib
from .enums import Backend, DampingModel, Integrator, Readback, SpringModel, VertexAttribute, coerce
from .errors import check

#: Presets: "current" is ``wethair_sim_desc_init`` (material springs, AUTO integrator: right
#: for any groom); "paper" is the paper scene's exact parameters (``wethair_sim_desc_default``'s
#: per-spring constants and symplectic Euler; drag and eq. 2's pull per point) in the current
#: layout.
PRESETS = ("current", "paper")

_ENUM_FIELDS = {
    "backend": Backend,
    "integrator": Integrator,
    "spring_model": SpringModel,
    "damping_model": DampingModel,
    "readback": Readback,
}
# Set by Simulation from its own arguments, never by keyword.
_POINTER_FIELDS = {"groom", "colliders", "collider_count", "collider_frames", "sdfs", "sdf_count", "struct_size"}


def sim_desc(preset: str = "current", **fields: Any) -> S.WetHairSimDesc:
    """A filled ``WetHairSimDesc``: the preset's defaults, then ``fields``.

    >>> d = sim_desc(backend="cpu", substeps=8, held_water={"enabled": True})
    """
    d = S.WetHairSimDesc()
    check(lib.wethair_sim_desc_init(C.byref(d), C.sizeof(d)))
    if preset == "paper":
        old = S.WetHairSimDesc()
        lib.wethair_sim_desc_default(C.byref(old))
        C.memmove(C.byref(d), C.byref(old), old.struct_size)  # the 0.1.0 prefix
        d.struct_size = C.sizeof(d)
        d.spring_model = SpringModel.PER_SPRING
        # The paper's drag and pull on every point alike (fields past the 0.1.0 prefix).
        d.air_drag_length = 0.0
        d.water_adhesion_length = 0.0
    elif preset != "current":
        raise ValueError(f"wethair: unknown preset {preset!r} (one of {', '.join(PRESETS)})")
    for name, value in fields.items():
        if name in _POINTER_FIELDS:
            raise TypeError(f"wethair: {name!r} is set by Simulation's own arguments")
        _assign(d, name, value, "")
    return d


def _assign(obj: C.Structure, name: str, value: Any, path: str) -> None:
    where = f"{path}{name}"
    kinds = dict(obj._fields_)
    if name not in kinds or name.startswith("reserved"):
        known = ", ".join(n for n, _ in obj._fields_ if not n.startswith("reserved") and n not in _POINTER_FIELDS)
        raise TypeError(f"wethair: no parameter {where!r} (known here: {known})")
    kind = kinds[name]
    if isinstance(kind, type) and issubclass(kind, C.Structure) and isinstance(value, Mapping):
        sub = getattr(obj, name)
        for k, v in value.items():
            if path == "" and name == "guides" and k == "strands":
                raise TypeError("wethair: guides['strands'] is passed as Simulation(guide_strands=...)")
            _assign(sub, k, v, f"{where}.")
        return
    if isinstance(kind, type) and issubclass(kind, C.Array):
        arr = getattr(obj, name)
        values = list(value)
        if len(values) != len(arr):
            raise ValueError(f"wethair: {where} takes {len(arr)} values, got {len(values)}")
        for i, v in enumerate(values):
            arr[i] = v
        return
    if path == "" and name in _ENUM_FIELDS:
        value = coerce(_ENUM_FIELDS[name], value)
    elif path == "" and name == "vertex_attributes" and not isinstance(value, int):
        flags = VertexAttribute(0)
        for v in value:
            flags |= coerce(VertexAttribute, v)
        value = flags
    elif path == "guides." and name == "choice":
        from .enums import GuideChoice

        value = coerce(GuideChoice, value)
    if isinstance(value, bool):
        value = int(value)
    setattr(obj, name, value)
