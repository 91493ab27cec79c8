"""The bake: simulates a hair Curves object with wethair over the scene's frame range and
stores every frame's point positions (object space) and wetness in a cache file, which
``cache.apply`` shows as the frame changes."""

import os
import tempfile
import time

import bpy
import numpy as np
from mathutils import Matrix, Vector

import wethair

from . import cache, collider
from .curves import positions, sizes, transform


class BakeError(Exception):
    """Why a bake could not run, in words for the artist."""


def _head_matrix(settings):
    """The head's rigid frame (or the world's when there is no head mesh)."""
    return collider.rigid(settings.collider.matrix_world) if settings.collider else Matrix.Identity(4)


def _cache_path(obj, settings) -> str:
    folder = settings.cache_dir or "//wethair_cache"
    if folder.startswith("//") and not bpy.data.filepath:
        folder = os.path.join(tempfile.gettempdir(), "wethair_cache")
    folder = bpy.path.abspath(folder)
    os.makedirs(folder, exist_ok=True)
    return os.path.join(folder, f"{bpy.path.clean_name(obj.name)}.npz")


def _emit(sim, settings, frame):
    """The emitter's spray cone or rain area for this frame (world space)."""
    e = settings.emitter
    if e is None or settings.rate <= 0.0:
        return
    m = e.matrix_world
    if settings.emitter_type == "SPRAY":
        axis = -(m.to_3x3() @ Vector((0.0, 0.0, 1.0))).normalized()
        sim.set_spray(
            origin=tuple(m.translation), direction=tuple(axis), half_angle=settings.spread,
            rate=settings.rate, speed=settings.speed, seed=settings.seed,
        )
    else:
        if e.type == "MESH":
            size = (e.dimensions.x, e.dimensions.y)
        else:
            s = e.empty_display_size if e.type == "EMPTY" else 1.0
            size = (2 * s * e.scale.x, 2 * s * e.scale.y)
        sim.set_rain(center=tuple(m.translation), size=size, rate=settings.rate, speed=settings.speed, seed=settings.seed)


def point_masses(points: np.ndarray, counts: np.ndarray, density: float) -> np.ndarray:
    """Each point's mass: ``density`` (kg/m) times half the length of its one or two segments."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    ends = np.cumsum(counts) - 1  # last point of each strand: its "segment" to the next strand is not one
    seg[ends[:-1]] = 0.0
    half = np.zeros(len(points))
    half[:-1] += seg / 2
    half[1:] += seg / 2
    # A strand with coincident points would weigh nothing: the library refuses that by name.
    return (density * half).astype(np.float32)


def bake(scene, obj, progress=None) -> str:
    """Bakes ``obj`` over ``scene``'s frame range; returns a one-line report. Raises
    ``BakeError`` or ``wethair.WetHairError`` (the library's code and message) on failure,
    leaving the object as it was."""
    if obj is None or obj.type != "CURVES":
        raise BakeError("select a hair Curves object")
    s = obj.wethair
    data = obj.data
    counts = sizes(data)
    if len(counts) == 0:
        raise BakeError(f"{obj.name} has no curves")
    start, end = scene.frame_start, scene.frame_end
    if end <= start:
        raise BakeError(f"the frame range {start}-{end} has nothing to bake")
    fps = scene.render.fps / scene.render.fps_base
    cache.free(obj, restore=True)  # bake from the rest shape

    scene.frame_set(start)
    rest_local = positions(data)
    world = transform(obj.matrix_world, rest_local)
    head0 = _head_matrix(s)
    groom_pts = transform(head0.inverted(), world)  # head space

    colliders, sdfs = [], []
    if s.collider is not None:
        if s.collider_shape == "SDF":
            sdfs.append(collider.sample_sdf(s.collider, s.sdf_resolution))
        elif s.collider_shape == "CAPSULE":
            colliders.append(collider.fit_capsule(collider.head_space_vertices(s.collider))[0])
        else:
            colliders.append(collider.fit_sphere(collider.head_space_vertices(s.collider))[0])

    params = dict(
        backend=s.backend,
        substeps=s.substeps,
        friction=s.friction,
        gravity=tuple(scene.gravity) if scene.use_gravity else (0.0, 0.0, 0.0),
        water={
            "r_min": s.reach_min,
            "r_max": s.reach_max,
            "adhesion": s.adhesion * 1e-3,
            "particle_mass": s.drop_mass * 1e-3,
            # Linear air drag that gives drops a 9 m/s terminal speed (a few-millimetre drop's).
            "drag": s.drop_mass * 1e-3 * 9.81 / 9.0,
        },
        held_water={"enabled": s.held_water, "dry_time": s.dry_time},
    )
    t0 = time.perf_counter()
    frames = end - start + 1
    out_pos = np.empty((frames, len(rest_local), 3), dtype=np.float32)
    out_wet = np.zeros((frames, len(rest_local)), dtype=np.float32)
    masses = point_masses(groom_pts, counts, s.linear_density * 1e-3)
    with wethair.Groom.from_strands(groom_pts, point_counts=counts, masses=masses) as groom, \
         wethair.Simulation(groom, colliders=colliders, sdfs=sdfs, **params) as sim:
        out_pos[0], out_wet[0] = rest_local, 0.0
        for i, frame in enumerate(range(start + 1, end + 1), start=1):
            scene.frame_set(frame)
            head = np.array(_head_matrix(s))
            sim.set_head_transform(head)
            if sdfs:
                sim.set_sdf_transform(0, head)
            _emit(sim, s, frame)
            sim.step(1.0 / fps)
            v = sim.vertices()
            lay = sim.layout
            p = v[:, lay.position_offset : lay.position_offset + 3]
            out_pos[i] = transform(np.linalg.inv(np.array(obj.matrix_world)), p)
            if lay.wetness_offset >= 0:
                out_wet[i] = v[:, lay.wetness_offset]
            if progress:
                progress(i, frames)
        stats = sim.stats()
        backend = sim.backend_info()
    path = _cache_path(obj, s)
    cache.save(path, start, out_pos, out_wet, rest_local)
    s.cache_file, s.bake_start, s.bake_end, s.baked = path, start, end, True
    s.last_error = ""
    ms = (time.perf_counter() - t0) * 1e3 / max(1, frames - 1)
    held = stats.water_held * wethair.WATER_QUANTUM_KG * 1e3
    s.last_report = (
        f"{len(counts)} strands, frames {start}-{end} on {backend.backend.name} ({backend.device}): "
        f"{ms:.1f} ms/frame, {stats.particles} drops, {held:.1f} g held"
    )
    scene.frame_set(start)
    cache.apply(scene)
    return s.last_report
