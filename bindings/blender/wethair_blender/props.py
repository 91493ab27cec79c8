"""The add-on's settings, one set per hair Curves object (``object.wethair``)."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty


def _is_mesh(_self, obj):
    return obj.type == "MESH"


class WetHairSettings(bpy.types.PropertyGroup):
    # The head
    collider: PointerProperty(
        name="Head", type=bpy.types.Object, poll=_is_mesh,
        description="Mesh the hair collides with; its motion carries the roots (head space = its frame at the first frame)",
    )
    collider_shape: EnumProperty(
        name="Shape",
        items=[
            ("SPHERE", "Sphere", "A sphere fitted to the mesh's vertices"),
            ("CAPSULE", "Capsule", "A capsule along the mesh's longest axis"),
            ("SDF", "SDF", "A signed distance field sampled from the mesh (closed meshes)"),
        ],
        default="SPHERE",
    )
    sdf_resolution: IntProperty(name="SDF cells", default=32, min=4, max=128, description="Cells along the longest side")
    # Water
    emitter: PointerProperty(name="Emitter", type=bpy.types.Object, description="Where water comes from (any object)")
    emitter_type: EnumProperty(
        name="Water",
        items=[
            ("SPRAY", "Spray cone", "A cone of drops from the emitter along its local -Z axis"),
            ("RAIN", "Rain area", "Drops falling from the emitter's rectangle (its X and Y size)"),
        ],
        default="SPRAY",
    )
    rate: FloatProperty(name="Drops/s", default=2000.0, min=0.0, soft_max=20000.0)
    speed: FloatProperty(name="Speed", default=2.0, min=0.0, soft_max=20.0, unit="VELOCITY")
    spread: FloatProperty(name="Spread", default=0.25, min=0.0, max=1.5, subtype="ANGLE", description="Spray cone half angle")
    drop_mass: FloatProperty(name="Drop mass (g)", default=0.05, min=0.0, soft_max=5.0, description="0.05 g: a 4.6 mm drop")
    reach_min: FloatProperty(name="Adhesion near (m)", default=0.002, min=0.0, precision=4, description="r_min of the paper's eq. 2")
    reach_max: FloatProperty(name="Adhesion far (m)", default=0.008, min=0.0, precision=4, description="r_max: no pull beyond it")
    adhesion: FloatProperty(
        name="Adhesion (mN)", default=0.2, min=0.0, soft_max=10.0,
        description="Peak pull of one drop on one hair point (eq. 2); 0.2 mN: surface tension around a 1 mm wisp",
    )
    seed: IntProperty(name="Seed", default=1, min=0)
    # Wet model
    held_water: BoolProperty(name="Held water", default=True, description="Water soaks in, weighs, bridges, drips and dries")
    dry_time: FloatProperty(name="Dry time (s)", default=1200.0, min=0.0, description="Time constant of drying in still air")
    # Hair
    linear_density: FloatProperty(
        name="Mass per metre (g/m)", default=1.0, min=0.0, soft_max=50.0,
        description="Each point weighs this times half its two segments' length, so the mass does not depend on how finely a curve is sampled",
    )
    substeps: IntProperty(name="Substeps", default=4, min=1, max=64)
    friction: FloatProperty(name="Friction", default=0.2, min=0.0, max=1.0)
    backend: EnumProperty(
        name="Backend",
        items=[("CPU", "CPU", "Multi-threaded CPU"), ("GPU", "GPU", "wgpu compute"), ("AUTO", "Auto", "The GPU where it is faster")],
        default="CPU",
    )
    # Output
    cache_dir: StringProperty(
        name="Cache", subtype="DIR_PATH", default="//wethair_cache",
        description="Folder for baked frames (a relative path needs a saved file; else the temporary folder)",
    )
    # State (written by the bake)
    baked: BoolProperty(name="Baked", default=False)
    bake_start: IntProperty(default=0)
    bake_end: IntProperty(default=0)
    cache_file: StringProperty(default="")
    last_error: StringProperty(name="Last error", default="")
    last_report: StringProperty(name="Last bake", default="")


def register():
    bpy.utils.register_class(WetHairSettings)
    bpy.types.Object.wethair = PointerProperty(type=WetHairSettings)


def unregister():
    del bpy.types.Object.wethair
    bpy.utils.unregister_class(WetHairSettings)
