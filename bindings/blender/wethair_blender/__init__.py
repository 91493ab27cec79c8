"""wethair for Blender: bakes a hair Curves object with wethair (wet hair that clumps, drips
and dries) into per-frame positions and a ``wetness`` point attribute.

Needs the ``wethair`` Python package (bindings/python): as a Blender 4.2+ extension its wheel
is listed in blender_manifest.toml; as a legacy add-on, install the wheel into Blender's Python.
"""

bl_info = {
    "name": "wethair",
    "author": "wethair developers",
    "version": (0, 1, 0),
    "blender": (4, 2, 0),
    "location": "Properties > Physics > Wet Hair",
    "description": "Real-time wet hair simulation for hair Curves",
    "category": "Physics",
}

import bpy  # noqa: E402

from . import cache, material, ops, panel, props  # noqa: E402


def register():
    props.register()
    for cls in ops.CLASSES + material.CLASSES + panel.CLASSES:
        bpy.utils.register_class(cls)
    cache.register()


def unregister():
    cache.unregister()
    for cls in reversed(ops.CLASSES + material.CLASSES + panel.CLASSES):
        bpy.utils.unregister_class(cls)
    props.unregister()
