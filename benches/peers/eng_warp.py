"""NVIDIA Warp on the CPU: one kernel launch per substep, one thread per point gathering
the (up to four) springs it belongs to, states ping-ponged (no atomics)."""

import numpy as np
import warp as wp

import scene as sc

MASS = wp.constant(sc.MASS)
GRAVITY = wp.constant(wp.vec3(*sc.GRAVITY))
STRETCH_K, STRETCH_C = wp.constant(sc.STRETCH_K), wp.constant(sc.STRETCH_C)
BEND_K, BEND_C = wp.constant(sc.BEND_K), wp.constant(sc.BEND_C)


@wp.func
def spring_on_b(xa: wp.vec3, xb: wp.vec3, va: wp.vec3, vb: wp.vec3, rest: float, k: float, c: float):
    d = xb - xa
    length = wp.length(d)
    u = d / length
    mag = k * (length - rest) + c * wp.dot(vb - va, u)
    return -mag * u


@wp.kernel
def substep(
    x: wp.array2d(dtype=wp.vec3),
    v: wp.array2d(dtype=wp.vec3),
    l1: wp.array2d(dtype=float),
    l2: wp.array2d(dtype=float),
    x_out: wp.array2d(dtype=wp.vec3),
    v_out: wp.array2d(dtype=wp.vec3),
    h: float,
):
    s, i = wp.tid()
    n = x.shape[1]
    if i == 0:
        x_out[s, i] = x[s, i]
        v_out[s, i] = v[s, i]
        return
    xi = x[s, i]
    vi = v[s, i]
    f = GRAVITY * MASS
    f += spring_on_b(x[s, i - 1], xi, v[s, i - 1], vi, l1[s, i - 1], STRETCH_K, STRETCH_C)
    if i + 1 < n:
        f -= spring_on_b(xi, x[s, i + 1], vi, v[s, i + 1], l1[s, i], STRETCH_K, STRETCH_C)
    if i >= 2:
        f += spring_on_b(x[s, i - 2], xi, v[s, i - 2], vi, l2[s, i - 2], BEND_K, BEND_C)
    if i + 2 < n:
        f -= spring_on_b(xi, x[s, i + 2], vi, v[s, i + 2], l2[s, i], BEND_K, BEND_C)
    vn = vi + h * f / MASS
    v_out[s, i] = vn
    x_out[s, i] = xi + h * vn


class Engine:
    name, variant = "warp", "point gather"

    def __init__(self, strands, points, threads):
        wp.config.quiet = True
        wp.init()
        self.version = wp.config.version
        self.backend = "cpu (LLVM JIT), launches run serially"
        x = sc.rest_positions(strands, points)
        l1, l2 = sc.rest_lengths(x)
        pad = lambda a: np.pad(a, ((0, 0), (0, points - a.shape[1])))
        dev = "cpu"
        self.x = [wp.array(x, dtype=wp.vec3, device=dev), wp.zeros_like(wp.array(x, dtype=wp.vec3, device=dev))]
        self.v = [wp.zeros(x.shape[:2], dtype=wp.vec3, device=dev), wp.zeros(x.shape[:2], dtype=wp.vec3, device=dev)]
        self.l1 = wp.array(pad(l1), dtype=float, device=dev)
        self.l2 = wp.array(pad(l2), dtype=float, device=dev)
        self.shape = x.shape[:2]
        self.h = sc.FRAME_DT / sc.SUBSTEPS
        self.cur = 0

    def step_frame(self):
        for _ in range(sc.SUBSTEPS):
            a, b = self.cur, 1 - self.cur
            wp.launch(
                substep,
                dim=self.shape,
                inputs=[self.x[a], self.v[a], self.l1, self.l2, self.x[b], self.v[b], self.h],
                device="cpu",
            )
            self.cur = b
        wp.synchronize()

    def positions(self):
        return self.x[self.cur].numpy().copy()
