"""A hair material that reads the bake's ``wetness`` point attribute: wet hair is darker and
glossier (water fills the gaps between fibres, so less light scatters back diffusely and the
surface turns specular)."""

import bpy

from .cache import WETNESS
from .curves import active_hair

DRY = (0.42, 0.26, 0.14, 1.0)
WET = (0.10, 0.06, 0.035, 1.0)


def wet_material(name="wethair wet hair"):
    """The material (made once): Attribute ``wetness`` mixes colour and roughness."""
    mat = bpy.data.materials.get(name)
    if mat is not None:
        return mat
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    bsdf = nodes.get("Principled BSDF")
    attr = nodes.new("ShaderNodeAttribute")
    attr.attribute_type = "GEOMETRY"
    attr.attribute_name = WETNESS
    colour = nodes.new("ShaderNodeMix")
    colour.data_type = "RGBA"
    colour.inputs["A"].default_value = DRY
    colour.inputs["B"].default_value = WET
    links.new(attr.outputs["Fac"], colour.inputs["Factor"])
    links.new(colour.outputs["Result"], bsdf.inputs["Base Color"])
    rough = nodes.new("ShaderNodeMapRange")
    rough.inputs["To Min"].default_value = 0.55
    rough.inputs["To Max"].default_value = 0.18
    links.new(attr.outputs["Fac"], rough.inputs["Value"])
    links.new(rough.outputs["Result"], bsdf.inputs["Roughness"])
    mat.diffuse_color = DRY  # the viewport's solid colour
    return mat


class WETHAIR_OT_wet_material(bpy.types.Operator):
    """Give the hair a material that turns darker and glossier where the bake says it is wet"""

    bl_idname = "wethair.add_wet_material"
    bl_label = "Add Wet Material"

    @classmethod
    def poll(cls, context):
        return active_hair(context) is not None

    def execute(self, context):
        mats = context.object.data.materials
        mat = wet_material()
        if mat.name not in mats:
            mats.append(mat)
        return {"FINISHED"}


CLASSES = (WETHAIR_OT_wet_material,)
