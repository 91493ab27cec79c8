"""Baked frames on disk (``.npz``: positions per frame, wetness per frame, the rest shape)
and the frame-change handler that shows them."""

import os

import bpy
import numpy as np
from bpy.app.handlers import persistent

from .curves import set_point_attribute, set_point_color, set_positions

#: The point attribute a material reads for the wet look (0 dry .. 1 soaked).
WETNESS = "wetness"
#: A colour from the wetness (dry light brown .. soaked dark), for the Workbench's Attribute colouring.
WET_COLOR = "wet_color"
_DRY, _WET = np.array([0.55, 0.36, 0.20, 1.0], np.float32), np.array([0.12, 0.07, 0.05, 1.0], np.float32)

_loaded = {}  # path -> (mtime, arrays)


def save(path, start, positions, wetness, rest) -> None:
    np.savez(path, start=np.int64(start), positions=positions, wetness=wetness, rest=rest)
    _loaded.pop(path, None)


def _load(path):
    mtime = os.path.getmtime(path)
    hit = _loaded.get(path)
    if hit is None or hit[0] != mtime:
        with np.load(path) as z:
            hit = (mtime, {k: z[k] for k in z.files})
        _loaded[path] = hit
    return hit[1]


def _show(obj, frame) -> None:
    s = obj.wethair
    if not (s.baked and s.cache_file and os.path.exists(s.cache_file)):
        return
    z = _load(s.cache_file)
    i = int(np.clip(frame - int(z["start"]), 0, len(z["positions"]) - 1))
    if len(z["positions"][i]) != len(obj.data.points):
        s.last_error = "the curves changed since the bake: bake again"
        return
    set_positions(obj.data, z["positions"][i])
    w = z["wetness"][i]
    set_point_attribute(obj.data, WETNESS, w)
    set_point_color(obj.data, WET_COLOR, _DRY + np.clip(w, 0, 1)[:, None] * (_WET - _DRY))


def apply(scene) -> None:
    """Shows every baked object's frame ``scene.frame_current``."""
    for obj in scene.objects:
        if obj.type == "CURVES" and obj.wethair.baked:
            _show(obj, scene.frame_current)


def free(obj, restore=True) -> None:
    """Forgets the bake (the file stays); with ``restore``, puts back the rest shape."""
    s = obj.wethair
    if s.baked and restore and s.cache_file and os.path.exists(s.cache_file):
        z = _load(s.cache_file)
        if len(z["rest"]) == len(obj.data.points):
            set_positions(obj.data, z["rest"])
    s.baked = False


@persistent
def on_frame_change(scene, _depsgraph=None):
    apply(scene)


def register():
    bpy.app.handlers.frame_change_post.append(on_frame_change)


def unregister():
    if on_frame_change in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.remove(on_frame_change)
