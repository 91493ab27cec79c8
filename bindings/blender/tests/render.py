"""Renders a baked hair object with the Workbench, headless, coloured by the ``wet_color``
attribute (dry light brown, soaked dark)."""

import math

import bpy


def setup_render(scene, hair, size=(480, 360), target=(0.0, 0.0, 0.03), distance=0.55):
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(cam)
    cam.location = (target[0], target[1] - distance * math.cos(0.3), target[2] + distance * math.sin(0.3))
    cam.rotation_euler = (math.pi / 2 - 0.3, 0.0, 0.0)
    cam.data.lens = 50
    scene.camera = cam
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    shading = scene.display.shading
    shading.light = "STUDIO"
    shading.color_type = "MATERIAL"
    shading.show_specular_highlight = True
    scene.render.film_transparent = False
    world = bpy.data.worlds.new("World")
    scene.world = world
    world.color = (0.1, 0.1, 0.12)


def render(scene, path):
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
