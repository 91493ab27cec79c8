"""Simulations: step the strands, add water, read vertices, water and statistics."""

from __future__ import annotations

import ctypes as C
from dataclasses import dataclass
from typing import Any, Optional, Sequence

import numpy as np

from . import _structs as S
from ._arrays import as_f32, as_u32, ptr
from ._handle import Handle
from ._lib import lib
from .desc import sim_desc
from .enums import Backend, ColliderShape, Integrator, Result
from .errors import InvalidArgumentError, check
from .groom import Groom

#: One water quantum: the ledger in ``Stats`` counts water in these (kg).
WATER_QUANTUM_KG = 1e-12


def sphere(center: Sequence[float], radius: float) -> S.WetHairCollider:
    """A sphere collider (head space, or its own frame with ``collider_frames``; m)."""
    return S.WetHairCollider(ColliderShape.SPHERE, tuple(center), (0.0, 0.0, 0.0), radius)


def capsule(a: Sequence[float], b: Sequence[float], radius: float) -> S.WetHairCollider:
    """A capsule collider from ``a`` to ``b`` (head space, or its own frame; m)."""
    return S.WetHairCollider(ColliderShape.CAPSULE, tuple(a), tuple(b), radius)


@dataclass
class Sdf:
    """A signed distance field collider: ``values`` shaped ``(nz, ny, nx)`` (x fastest, as
    the C struct), metres, negative inside; ``origin`` the centre of cell (0, 0, 0);
    ``transform`` a 4 x 4 matrix (translation in the last column) from the field to the world."""

    values: np.ndarray
    origin: Sequence[float]
    cell_size: float
    transform: Optional[np.ndarray] = None


@dataclass(frozen=True)
class VertexLayout:
    """Where each attribute sits in a vertex: offsets in floats (the C struct's are in
    bytes), -1 where the attribute is not output."""

    vertex_count: int
    strand_count: int
    stride: int
    position_offset: int
    tangent_offset: int
    wetness_offset: int


@dataclass(frozen=True)
class Advance:
    """What one ``Simulation.advance`` did."""

    steps: int
    blend: float
    dropped_time: float


@dataclass(frozen=True)
class BackendInfo:
    backend: Backend
    device: str
    fallback_reason: str


@dataclass(frozen=True)
class Stats:
    """``WetHairStats``: counts, timing, clumping, and the water ledger (in quanta of
    ``WATER_QUANTUM_KG``: added = in particles + held + left + evaporated, exactly)."""

    strands: int
    points: int
    particles: int
    particles_removed: int
    steps: int
    last_step_ms: float
    max_speed: float
    clumping: float
    threads: int
    integrator: Integrator
    backend: Backend
    clumping_along: float
    water_added: int
    water_in_particles: int
    water_held: int
    water_left: int
    water_evaporated: int
    error_estimate: float
    error_estimate_max: float
    substeps: int

    @property
    def water_held_kg(self) -> float:
        return self.water_held * WATER_QUANTUM_KG


def _matrix(m, name: str) -> np.ndarray:
    """A 4 x 4 matrix (translation in the last column) as the C side's 16 column-major floats."""
    a = np.asarray(m, dtype=np.float32)
    if a.shape != (4, 4):
        raise InvalidArgumentError(Result.ERROR_INVALID_ARGUMENT, f"{name}: expected a 4 x 4 matrix, got {a.shape}")
    return np.ascontiguousarray(a.T)


class Simulation(Handle):
    """A simulation (``WetHairSim``) of ``groom``.

    ``params`` are ``WetHairSimDesc`` fields by name over the ``preset``'s defaults (see
    ``wethair.sim_desc``): ``Simulation(groom, backend="cpu", substeps=8,
    held_water={"enabled": True})``. Colliders (``sphere``, ``capsule``), their own frames
    (``collider_frames``: one 4 x 4 matrix per collider, moved by ``set_collider_transform``;
    none: they follow the head), SDFs (``Sdf``) and a ``GIVEN`` guide list are copied at
    creation. Use as a context manager, or ``close()``."""

    _destroy = staticmethod(lib.wethair_sim_destroy)
    _what = "simulation"

    def __init__(
        self,
        groom: Groom,
        *,
        preset: str = "current",
        colliders: Sequence[S.WetHairCollider] = (),
        collider_frames: Optional[Sequence[Any]] = None,
        sdfs: Sequence[Sdf] = (),
        guide_strands: Optional[Sequence[int]] = None,
        **params: Any,
    ):
        super().__init__()
        d = sim_desc(preset, **params)
        d.groom = groom.handle
        cols = (S.WetHairCollider * max(1, len(colliders)))(*colliders)
        if colliders:
            d.colliders, d.collider_count = C.cast(cols, C.POINTER(S.WetHairCollider)), len(colliders)
        keep = []  # arrays the desc points into, alive until the call returns
        if collider_frames is not None:
            if len(collider_frames) != len(colliders):
                raise InvalidArgumentError(
                    Result.ERROR_INVALID_ARGUMENT,
                    f"collider_frames: one 4 x 4 matrix per collider, got {len(collider_frames)} for {len(colliders)}",
                )
            if colliders:
                frames = np.concatenate([_matrix(m, f"collider_frames[{i}]").ravel() for i, m in enumerate(collider_frames)])
                keep.append(frames)
                d.collider_frames = ptr(frames, C.c_float)
        if sdfs:
            arr = (S.WetHairSdf * len(sdfs))()
            for i, s in enumerate(sdfs):
                v = as_f32(s.values, (-1, -1, -1), f"sdfs[{i}].values")
                keep.append(v)
                arr[i].dims[:] = [v.shape[2], v.shape[1], v.shape[0]]
                arr[i].origin[:] = list(s.origin)
                arr[i].cell_size = s.cell_size
                arr[i].values = ptr(v, C.c_float)
                arr[i].transform[:] = list(_matrix(np.eye(4) if s.transform is None else s.transform, "transform").ravel())
            d.sdfs, d.sdf_count = C.cast(arr, C.POINTER(S.WetHairSdf)), len(sdfs)
        if guide_strands is not None:
            g = as_u32(guide_strands, (-1,), "guide_strands")
            keep.append(g)
            d.guides.strands = ptr(g, C.c_uint32)
            if d.guides.count == 0:
                d.guides.count = len(g)
        h = C.c_void_p()
        check(lib.wethair_sim_create(C.byref(d), C.byref(h)))
        self._h = h
        lay = S.WetHairVertexLayout(struct_size=C.sizeof(S.WetHairVertexLayout))
        check(lib.wethair_sim_get_vertex_layout(h, C.byref(lay)))
        floats = lambda b: b // 4 if b >= 0 else -1  # noqa: E731
        self.layout = VertexLayout(
            lay.vertex_count,
            lay.strand_count,
            lay.stride_floats,
            floats(lay.position_offset),
            floats(lay.tangent_offset),
            floats(lay.wetness_offset),
        )
        self.water_capacity = d.water.capacity
        self.point_counts = groom.point_counts

    # -- stepping ---------------------------------------------------------------------------

    def step(self, dt: float = 1.0 / 60.0) -> None:
        """Advances ``dt`` seconds (the desc's substeps)."""
        check(lib.wethair_sim_step(self.handle, dt))

    def advance(self, frame_time: float) -> Advance:
        """Advances by the host's frame time in fixed steps (a desc with ``fixed_step``)."""
        a = S.WetHairAdvance(struct_size=C.sizeof(S.WetHairAdvance))
        check(lib.wethair_sim_advance(self.handle, frame_time, C.byref(a)))
        return Advance(a.steps, a.blend, a.dropped_time)

    def reset(self) -> None:
        """Back to rest, on the current head transform; water cleared."""
        check(lib.wethair_sim_reset(self.handle))

    # -- what moves the hair ---------------------------------------------------------------------

    def set_head_transform(self, matrix) -> None:
        """The head's 4 x 4 transform (translation in the last column) at the end of the next step."""
        check(lib.wethair_sim_set_head_transform(self.handle, ptr(_matrix(matrix, "matrix"), C.c_float)))

    def set_sdf_transform(self, index: int, matrix) -> None:
        check(lib.wethair_sim_set_sdf_transform(self.handle, index, ptr(_matrix(matrix, "matrix"), C.c_float)))

    def set_collider_transform(self, index: int, matrix) -> None:
        """Collider ``index``'s own frame (4 x 4) at the end of the next step (a simulation made
        with ``collider_frames``)."""
        check(lib.wethair_sim_set_collider_transform(self.handle, index, ptr(_matrix(matrix, "matrix"), C.c_float)))

    def set_root_frames(self, positions, rotations) -> None:
        """Every root's position ``(strands, 3)`` and unit quaternion ``(strands, 4)``, x y z w."""
        p = as_f32(positions, (-1, 3), "positions")
        r = as_f32(rotations, (-1, 4), "rotations")
        if len(p) != len(r):
            raise InvalidArgumentError(
                Result.ERROR_INVALID_ARGUMENT, f"{len(p)} positions but {len(r)} rotations"
            )
        check(lib.wethair_sim_set_root_frames(self.handle, ptr(p, C.c_float), ptr(r, C.c_float), len(p)))

    def set_guide_fraction(self, fraction: float) -> None:
        check(lib.wethair_sim_set_guide_fraction(self.handle, fraction))

    # -- water and weather ----------------------------------------------------------------------

    def add_water(self, positions, velocities=None) -> None:
        """Water particles at ``positions`` ``(n, 3)`` (m, world), optionally with velocities."""
        p = as_f32(positions, (-1, 3), "positions")
        v = None if velocities is None else as_f32(velocities, (len(p), 3), "velocities")
        check(lib.wethair_sim_add_water(self.handle, ptr(p, C.c_float), ptr(v, C.c_float), len(p)))

    def clear_water(self) -> None:
        check(lib.wethair_sim_clear_water(self.handle))

    def soak(self, saturation: float = 1.0) -> None:
        """Fills every hair point's held water to ``saturation`` times its hold limit (the wet
        model; 0..10: above 1 the excess runs down the strands and drips)."""
        check(lib.wethair_sim_soak(self.handle, saturation))

    def set_wind(self, velocity: Sequence[float] = (0.0, 0.0, 0.0), gust: float = 0.0, seed: int = 0) -> None:
        w = S.WetHairWind(tuple(velocity), gust, seed)
        check(lib.wethair_sim_set_wind(self.handle, C.byref(w)))

    def set_rain(self, center=None, size=(0.4, 0.4), rate: float = 500.0, speed: float = 4.0, seed: int = 1) -> None:
        """Rain over ``size`` (x, y metres) around ``center``, ``rate`` drops a second; None stops it."""
        if center is None:
            check(lib.wethair_sim_set_rain(self.handle, None))
            return
        r = S.WetHairRain(tuple(center), tuple(size), rate, speed, seed)
        check(lib.wethair_sim_set_rain(self.handle, C.byref(r)))

    def set_spray(
        self, origin=None, direction=(0.0, 0.0, -1.0), half_angle: float = 0.2, rate: float = 500.0,
        speed: float = 3.0, seed: int = 1,
    ) -> None:
        """A cone of drops from ``origin`` along ``direction``; None stops it."""
        if origin is None:
            check(lib.wethair_sim_set_spray(self.handle, None))
            return
        s = S.WetHairSpray(tuple(origin), tuple(direction), half_angle, rate, speed, seed)
        check(lib.wethair_sim_set_spray(self.handle, C.byref(s)))

    # -- output ------------------------------------------------------------------------------

    def vertices(self, out: Optional[np.ndarray] = None) -> np.ndarray:
        """The vertex buffer, ``(vertex_count, stride)`` float32, copied once from the
        library straight into ``out`` when given (C-contiguous float32 of that size)."""
        lay = self.layout
        shape = (lay.vertex_count, lay.stride)
        if out is None:
            out = np.empty(shape, dtype=np.float32)
        elif out.dtype != np.float32 or not out.flags.c_contiguous or out.size != lay.vertex_count * lay.stride:
            raise InvalidArgumentError(
                Result.ERROR_INVALID_ARGUMENT, f"out: expected a C-contiguous float32 array of {shape}"
            )
        written = C.c_size_t()
        check(lib.wethair_sim_get_vertex_buffer(self.handle, ptr(out, C.c_float), out.size, C.byref(written)))
        return out.reshape(shape)

    def positions(self) -> np.ndarray:
        """Every vertex's position, ``(vertex_count, 3)`` (a view into a fresh vertex copy)."""
        o = self.layout.position_offset
        return self.vertices()[:, o : o + 3]

    def strands(self) -> np.ndarray:
        """Positions as ``(strands, points, 3)`` when every strand has the same point count."""
        lay = self.layout
        counts = self.point_counts
        uneven = lay.vertex_count % lay.strand_count or (counts is not None and len(set(counts.tolist())) > 1)
        if uneven:
            raise ValueError("wethair: strands differ in point count; use positions()")
        return self.positions().reshape(lay.strand_count, -1, 3)

    def wetness(self) -> np.ndarray:
        """Every vertex's wetness 0..1 (needs the WETNESS attribute)."""
        o = self.layout.wetness_offset
        if o < 0:
            raise ValueError("wethair: the simulation does not output wetness")
        return self.vertices()[:, o]

    def water(self) -> np.ndarray:
        """The water particles' positions, ``(particles, 3)``."""
        out = np.empty((max(1, self.water_capacity), 3), dtype=np.float32)
        n = C.c_uint32()
        check(lib.wethair_sim_get_water(self.handle, ptr(out, C.c_float), self.water_capacity, C.byref(n)))
        return out[: n.value]

    def stats(self) -> Stats:
        """Counters and measures (the measures are taken now: a search over the strands)."""
        return self._stats(lib.wethair_sim_get_stats)

    def counters(self) -> Stats:
        """The counters of :meth:`stats` without its measures (those are -1): for every frame."""
        return self._stats(lib.wethair_sim_get_counters)

    def _stats(self, fill) -> Stats:
        s = S.WetHairStats(struct_size=C.sizeof(S.WetHairStats))
        check(fill(self.handle, C.byref(s)))
        vals = {f: getattr(s, f) for f in Stats.__dataclass_fields__}
        vals["integrator"] = Integrator(vals["integrator"])
        vals["backend"] = Backend(vals["backend"])
        return Stats(**vals)

    def backend_info(self) -> BackendInfo:
        b = S.WetHairBackendInfo(struct_size=C.sizeof(S.WetHairBackendInfo))
        check(lib.wethair_sim_get_backend_info(self.handle, C.byref(b)))
        return BackendInfo(Backend(b.backend), b.device.decode("utf-8", "replace"), b.fallback_reason.decode("utf-8", "replace"))
