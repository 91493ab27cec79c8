"""Builds the test scene by script in a fresh Blender: a 0.1 m UV sphere head at the origin,
a hair Curves object of strands rooted on its upper half along the normals, an empty above
in front of it as the water emitter (a spray cone at the hanging hair), and the add-on's settings."""

import bpy
import numpy as np

RADIUS = 0.1


def roots_on_sphere(n, seed=7):
    """n roots spread over the upper half of the sphere (a Fibonacci spiral, z > 0.2 r)."""
    k = np.arange(n) + 0.5
    z = 0.2 + 0.8 * k / n
    phi = k * np.pi * (3 - np.sqrt(5))
    rho = np.sqrt(1 - z * z)
    return RADIUS * np.stack([rho * np.cos(phi), rho * np.sin(phi), z], axis=1)


def build(strands=2000, points=8, length=0.15):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, 31  # 30 simulated frames
    scene.render.fps = 30
    bpy.ops.mesh.primitive_uv_sphere_add(radius=RADIUS, segments=32, ring_count=16)
    head = bpy.context.object
    head.name = "Head"
    roots = roots_on_sphere(strands)
    normals = roots / RADIUS
    t = np.linspace(0.0, length, points)
    pts = roots[:, None, :] + t[None, :, None] * normals[:, None, :]
    curves = bpy.data.hair_curves.new("Hair")
    curves.add_curves([points] * strands)
    curves.points.foreach_set("position", pts.astype(np.float32).ravel())
    hair = bpy.data.objects.new("Hair", curves)
    scene.collection.objects.link(hair)
    emitter = bpy.data.objects.new("Rain", None)
    emitter.location = (0.0, 0.0, 0.3)
    emitter.empty_display_size = 0.15  # a 30 cm square
    emitter.empty_display_type = "PLAIN_AXES"
    scene.collection.objects.link(emitter)
    s = hair.wethair
    s.collider = head
    s.collider_shape = "SPHERE"
    s.backend = "CPU"
    s.emitter_type = "RAIN"
    s.rate = 5000.0
    bpy.context.view_layer.objects.active = hair
    hair.select_set(True)
    return scene, hair, head, emitter


def tip_spacing(positions, points):
    """Mean distance from each strand's tip to the nearest other tip (smaller: clumped)."""
    tips = positions.reshape(-1, points, 3)[:, -1]
    d = np.linalg.norm(tips[:, None] - tips[None, :], axis=2)
    np.fill_diagonal(d, np.inf)
    return float(d.min(axis=1).mean())
