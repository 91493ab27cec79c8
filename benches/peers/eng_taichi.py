"""Taichi on the CPU: one kernel per substep, one iteration per point gathering the (up to
four) springs it belongs to, states ping-ponged (no atomics); `threads` worker threads."""

import numpy as np
import taichi as ti

import scene as sc


class Engine:
    name, variant = "taichi", "point gather"

    def __init__(self, strands, points, threads):
        ti.init(arch=ti.cpu, cpu_max_num_threads=max(threads, 1), default_fp=ti.f32, offline_cache=True, log_level=ti.ERROR)
        self.version = ".".join(str(n) for n in ti.__version__)
        self.backend = f"ti.cpu, {max(threads, 1)} thread{'s' if threads > 1 else ''}"
        x = sc.rest_positions(strands, points)
        l1, l2 = sc.rest_lengths(x)
        pad = lambda a: np.pad(a, ((0, 0), (0, points - a.shape[1])))
        shape = x.shape[:2]
        self.x = [ti.Vector.field(3, ti.f32, shape=shape) for _ in range(2)]
        self.v = [ti.Vector.field(3, ti.f32, shape=shape) for _ in range(2)]
        self.l1 = ti.field(ti.f32, shape=shape)
        self.l2 = ti.field(ti.f32, shape=shape)
        self.x[0].from_numpy(x)
        self.x[1].from_numpy(x)
        self.l1.from_numpy(pad(l1))
        self.l2.from_numpy(pad(l2))
        self.cur = 0
        h = sc.FRAME_DT / sc.SUBSTEPS
        m, g = sc.MASS, ti.Vector(list(sc.GRAVITY))
        ks, cs, kb, cb = sc.STRETCH_K, sc.STRETCH_C, sc.BEND_K, sc.BEND_C

        @ti.func
        def on_b(xa, xb, va, vb, rest, k, c):
            d = xb - xa
            length = d.norm()
            u = d / length
            return -(k * (length - rest) + c * (vb - va).dot(u)) * u

        @ti.kernel
        def substep(x: ti.template(), v: ti.template(), xo: ti.template(), vo: ti.template()):
            for s, i in x:
                n = x.shape[1]
                if i == 0:
                    xo[s, i] = x[s, i]
                    vo[s, i] = v[s, i]
                else:
                    xi, vi = x[s, i], v[s, i]
                    f = g * m
                    f += on_b(x[s, i - 1], xi, v[s, i - 1], vi, self.l1[s, i - 1], ks, cs)
                    if i + 1 < n:
                        f -= on_b(xi, x[s, i + 1], vi, v[s, i + 1], self.l1[s, i], ks, cs)
                    if i >= 2:
                        f += on_b(x[s, i - 2], xi, v[s, i - 2], vi, self.l2[s, i - 2], kb, cb)
                    if i + 2 < n:
                        f -= on_b(xi, x[s, i + 2], vi, v[s, i + 2], self.l2[s, i], kb, cb)
                    vn = vi + h * f / m
                    vo[s, i] = vn
                    xo[s, i] = xi + h * vn

        self.substep = substep

    def step_frame(self):
        for _ in range(sc.SUBSTEPS):
            a, b = self.cur, 1 - self.cur
            self.substep(self.x[a], self.v[a], self.x[b], self.v[b])
            self.cur = b
        ti.sync()

    def positions(self):
        return self.x[self.cur].to_numpy().copy()
