"""Operators: bake (with a progress bar), free the bake."""

import bpy

import wethair

from . import cache
from .bake import BakeError, bake
from .curves import active_hair


class WETHAIR_OT_bake(bpy.types.Operator):
    """Simulate the active hair Curves object with wethair over the scene's frame range"""

    bl_idname = "wethair.bake"
    bl_label = "Bake Wet Hair"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        return active_hair(context) is not None

    def execute(self, context):
        obj = context.object
        wm = context.window_manager
        wm.progress_begin(0, 100)
        try:
            report = bake(context.scene, obj, progress=lambda i, n: wm.progress_update(int(100 * i / n)))
        except (BakeError, wethair.WetHairError, ValueError, TypeError) as e:
            # The library refused a parameter or the scene: say why; the object is as it was.
            msg = str(e)
            obj.wethair.last_error = msg
            self.report({"ERROR"}, f"wethair: {msg}")
            return {"CANCELLED"}
        finally:
            wm.progress_end()
        self.report({"INFO"}, f"wethair: {report}")
        return {"FINISHED"}


class WETHAIR_OT_free(bpy.types.Operator):
    """Forget the bake and put back the rest shape"""

    bl_idname = "wethair.free_bake"
    bl_label = "Free Bake"

    @classmethod
    def poll(cls, context):
        hair = active_hair(context)
        return hair is not None and hair.wethair.baked

    def execute(self, context):
        cache.free(context.object, restore=True)
        return {"FINISHED"}


CLASSES = (WETHAIR_OT_bake, WETHAIR_OT_free)
