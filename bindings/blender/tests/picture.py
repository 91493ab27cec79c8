"""The README's picture: the test scene (2,000 strands on a 0.1 m sphere) after 1 s, dry
(left) and under 1 s of rain (right), baked by the add-on and rendered headless by Blender's
EEVEE with the add-on's wet material; the two renders side by side in one PNG.

    python picture.py OUT.png        (scripts/python.sh picture)
"""

import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [os.path.dirname(HERE), HERE]

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import scene as S  # noqa: E402
import wethair_blender  # noqa: E402
from wethair_blender.material import wet_material  # noqa: E402

W, H = 400, 360


def render(wet, path):
    scene, hair, head, emitter = S.build()
    if wet:
        hair.wethair.emitter = emitter
    assert bpy.ops.wethair.bake() == {"FINISHED"}, hair.wethair.last_error
    print(hair.wethair.last_report)
    scene.frame_set(scene.frame_end)
    hair.data.materials.append(wet_material())
    skin = bpy.data.materials.new("skin")
    skin.diffuse_color = (0.8, 0.62, 0.52, 1.0)
    skin.use_nodes = True
    skin.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.8, 0.62, 0.52, 1.0)
    head.data.materials.append(skin)
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(cam)
    cam.location = (0.0, -0.62 * math.cos(0.25), 0.62 * math.sin(0.25) - 0.02)
    cam.rotation_euler = (math.pi / 2 - 0.25, 0.0, 0.0)
    scene.camera = cam
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.energy = 4.0
    sun.rotation_euler = (0.7, 0.3, -0.6)
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.05, 0.05, 0.06, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 3.0
    scene.world = world
    scene.render.engine = "BLENDER_EEVEE_NEXT"
    scene.eevee.taa_render_samples = 16
    scene.render.resolution_x, scene.render.resolution_y = W, H
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)


def main(out):
    wethair_blender.register()
    parts = []
    for wet in (False, True):
        path = f"{out}.{'wet' if wet else 'dry'}.png"
        render(wet, path)
        img = bpy.data.images.load(path)
        px = np.array(img.pixels[:], dtype=np.float32).reshape(H, W, 4)
        parts.append(px)
        os.remove(path)
    both = np.concatenate(parts, axis=1)
    img = bpy.data.images.new("both", 2 * W, H)
    img.pixels.foreach_set(both.ravel())
    img.filepath_raw = out
    img.file_format = "PNG"
    img.save()
    print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1])
    sys.stdout.flush()
    os._exit(0)  # see tests/conftest.py: bpy's exit handlers can hang
