"""The panel: Properties editor, Physics tab, on hair Curves objects."""

import bpy

from .curves import active_hair


class WETHAIR_PT_panel(bpy.types.Panel):
    bl_label = "Wet Hair (wethair)"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "physics"

    @classmethod
    def poll(cls, context):
        return active_hair(context) is not None

    def draw(self, context):
        s = context.object.wethair
        col = self.layout.column()
        box = col.box()
        box.label(text="Head")
        box.prop(s, "collider")
        row = box.row()
        row.prop(s, "collider_shape", expand=True)
        if s.collider_shape == "SDF":
            box.prop(s, "sdf_resolution")
        box = col.box()
        box.label(text="Water")
        box.prop(s, "emitter")
        box.row().prop(s, "emitter_type", expand=True)
        for name in ("rate", "speed", "spread", "drop_mass", "reach_min", "reach_max", "adhesion", "seed"):
            if name != "spread" or s.emitter_type == "SPRAY":
                box.prop(s, name)
        box.prop(s, "held_water")
        if s.held_water:
            box.prop(s, "dry_time")
        box = col.box()
        box.label(text="Hair")
        for name in ("linear_density", "substeps", "friction", "backend", "cache_dir"):
            box.prop(s, name)
        row = col.row()
        row.scale_y = 1.4
        row.operator("wethair.bake", icon="PHYSICS")
        row.operator("wethair.free_bake", icon="TRASH")
        col.operator("wethair.add_wet_material", icon="MATERIAL")
        if s.last_error:
            col.label(text=s.last_error, icon="ERROR")
        elif s.last_report:
            col.label(text=s.last_report, icon="INFO")


CLASSES = (WETHAIR_PT_panel,)
