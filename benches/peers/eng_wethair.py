"""wethair through its C ABI (ctypes on libwethair.so): the paper scene's exact parameters
(`wethair_sim_desc_default`), the CPU backend with `threads` workers, positions only."""

import ctypes as C
import os

import numpy as np

import scene as sc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


class Spring(C.Structure):
    _fields_ = [("stiffness", C.c_float), ("damping", C.c_float)]


class Water(C.Structure):
    _fields_ = [(n, C.c_float) for n in ("r_min", "r_max", "adhesion", "particle_mass", "drag")] + [
        ("capacity", C.c_uint32),
        ("wetting_rate", C.c_float),
        ("domain_radius", C.c_float),
    ]


class SimDesc(C.Structure):
    """The 0.1.0 layout of WetHairSimDesc (128 bytes), which every later library accepts."""

    _fields_ = [
        ("struct_size", C.c_uint32),
        ("damping_model", C.c_uint32),
        ("groom", C.c_void_p),
        ("stretch", Spring),
        ("bend", Spring),
        ("gravity", C.c_float * 3),
        ("air_drag", C.c_float),
        ("substeps", C.c_uint32),
        ("integrator", C.c_uint32),
        ("solver_iterations", C.c_uint32),
        ("threads", C.c_uint32),
        ("water", Water),
        ("colliders", C.c_void_p),
        ("collider_count", C.c_uint32),
        ("friction", C.c_float),
        ("vertex_attributes", C.c_uint32),
        ("backend", C.c_uint32),
        ("readback", C.c_uint32),
    ]


class VertexLayout(C.Structure):
    _fields_ = [(n, C.c_uint32) for n in ("struct_size", "vertex_count", "strand_count", "stride_floats")] + [
        (n, C.c_int32) for n in ("position_offset", "tangent_offset", "wetness_offset")
    ]


def load():
    path = os.environ.get("WETHAIR_LIB", os.path.join(ROOT, "target", "release", "libwethair.so"))
    lib = C.CDLL(path)
    lib.wethair_version_string.restype = C.c_char_p
    lib.wethair_last_error_message.restype = C.c_char_p
    return lib


class Engine:
    name, variant = "wethair", "CPU backend"

    def __init__(self, strands, points, threads):
        assert C.sizeof(SimDesc) == 128
        self.lib = lib = load()
        self.version = lib.wethair_version_string().decode()
        self.threads = threads
        self.backend = f"cpu, {threads} thread{'s' if threads > 1 else ''}"
        self.shape = (strands, points)
        groom = C.c_void_p()
        self._check(lib.wethair_groom_create_paper_scene(strands, points, C.byref(groom)))
        d = SimDesc()
        lib.wethair_sim_desc_default(C.byref(d))
        d.groom = groom
        d.threads = threads
        d.backend = 1  # WETHAIR_BACKEND_CPU
        d.vertex_attributes = 1  # WETHAIR_ATTRIBUTE_POSITION
        self.sim = C.c_void_p()
        self._check(lib.wethair_sim_create(C.byref(d), C.byref(self.sim)))
        lib.wethair_groom_destroy(groom)
        lay = VertexLayout(struct_size=C.sizeof(VertexLayout))
        self._check(lib.wethair_sim_get_vertex_layout(self.sim, C.byref(lay)))
        self.buf = np.zeros(lay.vertex_count * lay.stride_floats, dtype=np.float32)

    def _check(self, r):
        if r != 0:
            raise RuntimeError(self.lib.wethair_last_error_message().decode())

    def step_frame(self):
        self._check(self.lib.wethair_sim_step(self.sim, C.c_float(sc.FRAME_DT)))

    def positions(self):
        written = C.c_size_t()
        ptr = self.buf.ctypes.data_as(C.POINTER(C.c_float))
        self._check(self.lib.wethair_sim_get_vertex_buffer(self.sim, ptr, self.buf.size, C.byref(written)))
        return self.buf.reshape(self.shape[0], self.shape[1], 3).copy()

    def __del__(self):
        if getattr(self, "sim", None):
            self.lib.wethair_sim_destroy(self.sim)
