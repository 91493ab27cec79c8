"""NumPy: the scene vectorised over strands, float32, single-threaded."""

import numpy as np

import scene as sc


class Engine:
    name, variant = "numpy", "vectorised"

    def __init__(self, strands, points, threads):
        self.version = np.__version__
        self.backend = "cpu, 1 thread"
        self.x = sc.rest_positions(strands, points)
        self.v = np.zeros_like(self.x)
        self.l1, self.l2 = sc.rest_lengths(self.x)
        self.g = np.array(sc.GRAVITY, dtype=np.float32) * np.float32(sc.MASS)
        self.h = np.float32(sc.FRAME_DT / sc.SUBSTEPS)

    def _springs(self, f, gap, k, c, rest):
        x, v = self.x, self.v
        d = x[:, gap:] - x[:, :-gap]
        length = np.sqrt(np.einsum("spk,spk->sp", d, d))
        u = d / length[..., None]
        dv = v[:, gap:] - v[:, :-gap]
        mag = np.float32(k) * (length - rest) + np.float32(c) * np.einsum("spk,spk->sp", dv, u)
        fa = mag[..., None] * u
        f[:, :-gap] += fa
        f[:, gap:] -= fa

    def step_frame(self):
        h, inv_m = self.h, np.float32(1.0 / sc.MASS)
        for _ in range(sc.SUBSTEPS):
            f = np.broadcast_to(self.g, self.x.shape).copy()
            self._springs(f, 1, sc.STRETCH_K, sc.STRETCH_C, self.l1)
            self._springs(f, 2, sc.BEND_K, sc.BEND_C, self.l2)
            self.v[:, 1:] += h * inv_m * f[:, 1:]
            self.x[:, 1:] += h * self.v[:, 1:]

    def positions(self):
        return self.x.copy()
