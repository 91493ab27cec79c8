"""The paper scene every engine in this comparison simulates, defined once.

Roots: `strands` points spread evenly by area over the upper half of a 0.1 m sphere (a
Fibonacci spiral), pinned. Each strand: `points` points 0.02 m apart along the outward
normal, 1 g each. Springs: stretch (i, i+1) k = 40 N/m, c = 0.02 N s/m; bend (i, i+2)
k = 10 N/m, c = 0.005 N s/m; damping along the spring only:
    f_a = (k (|d| - l) + c (v_b - v_a) . u) u,  f_b = -f_a,  d = x_b - x_a, u = d / |d|.
Gravity (0, 0, -9.81). Symplectic Euler, 4 substeps per 1/60 s frame. No collisions.
wethair's `wethair_groom_create_paper_scene` builds the same positions bit for bit (both
compute in double precision and round once).
"""

import math

import numpy as np

R_HEAD = 0.1
SEGMENT = 0.02
MASS = 1e-3
STRETCH_K, STRETCH_C = 40.0, 0.02
BEND_K, BEND_C = 10.0, 0.005
GRAVITY = (0.0, 0.0, -9.81)
SUBSTEPS = 4
FRAME_DT = 1.0 / 60.0

SCENES = {
    "paper": (10_000, 6),
    "big": (100_000, 16),
    "tiny": (500, 6),
}


def rest_positions(strands, points):
    """(strands, points, 3) float32 rest positions, strand-major."""
    i = np.arange(strands, dtype=np.float64)
    z = 1.0 - (i + 0.5) / strands
    r = np.sqrt(np.maximum(1.0 - z * z, 0.0))
    phi = i * math.pi * (3.0 - math.sqrt(5.0))
    normal = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    off = R_HEAD + SEGMENT * np.arange(points, dtype=np.float64)
    return (normal[:, None, :] * off[None, :, None]).astype(np.float32)


def rest_lengths(x):
    """Rest lengths of the stretch (gap 1) and bend (gap 2) springs, float32, per strand."""
    l1 = np.linalg.norm(x[:, 1:] - x[:, :-1], axis=2).astype(np.float32)
    l2 = np.linalg.norm(x[:, 2:] - x[:, :-2], axis=2).astype(np.float32)
    return l1, l2


def sanity(x, rest):
    """(max |coordinate|, max distance from the origin, max segment strain) of a state."""
    seg = np.linalg.norm(x[:, 1:] - x[:, :-1], axis=2)
    l0 = np.linalg.norm(rest[:, 1:] - rest[:, :-1], axis=2)
    return (
        float(np.abs(x).max()),
        float(np.linalg.norm(x, axis=2).max()),
        float(np.abs(seg / l0 - 1.0).max()),
    )
