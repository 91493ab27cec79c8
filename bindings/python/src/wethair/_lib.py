"""Loads the wethair C library and declares every entry point's argument and result types.

The library is found, in order: at ``$WETHAIR_LIBRARY`` (a path), beside this file (where a
wheel carries it), then by the system's loader (``ctypes.util.find_library("wethair")``).
"""

import ctypes as C
import ctypes.util
import os
import sys

from . import _structs as S

_NAMES = {"linux": "libwethair.so", "darwin": "libwethair.dylib", "win32": "wethair.dll"}

P = C.POINTER
f32p, u32p, u8p, vp = P(C.c_float), P(C.c_uint32), P(C.c_uint8), C.c_void_p
R = C.c_uint32  # WetHairResult

# name: (result type, argument types)
_PROTOTYPES = {
    "wethair_version": (C.c_uint32, []),
    "wethair_version_string": (C.c_char_p, []),
    "wethair_result_string": (C.c_char_p, [C.c_uint32]),
    "wethair_last_error_message": (C.c_char_p, []),
    "wethair_groom_create": (R, [P(S.WetHairGroomDesc), P(vp)]),
    "wethair_groom_create_paper_scene": (R, [C.c_uint32, C.c_uint32, P(vp)]),
    "wethair_groom_load_with_desc": (R, [C.c_char_p, P(S.WetHairLoadDesc), P(vp)]),
    "wethair_groom_get_load_message": (C.c_char_p, [vp]),
    "wethair_groom_get_counts": (R, [vp, u32p, u32p]),
    "wethair_groom_destroy": (None, [vp]),
    "wethair_load_desc_default": (None, [P(S.WetHairLoadDesc)]),
    "wethair_sim_desc_default": (None, [P(S.WetHairSimDesc)]),
    "wethair_sim_desc_init": (R, [P(S.WetHairSimDesc), C.c_uint32]),
    "wethair_sim_create": (R, [P(S.WetHairSimDesc), P(vp)]),
    "wethair_sim_destroy": (None, [vp]),
    "wethair_sim_set_head_transform": (R, [vp, f32p]),
    "wethair_sim_set_sdf_transform": (R, [vp, C.c_uint32, f32p]),
    "wethair_sim_set_collider_transform": (R, [vp, C.c_uint32, f32p]),
    "wethair_sim_set_guide_fraction": (R, [vp, C.c_float]),
    "wethair_sim_set_root_frames": (R, [vp, f32p, f32p, C.c_uint32]),
    "wethair_sim_add_water": (R, [vp, f32p, f32p, C.c_uint32]),
    "wethair_sim_clear_water": (R, [vp]),
    "wethair_sim_step": (R, [vp, C.c_float]),
    "wethair_sim_advance": (R, [vp, C.c_float, P(S.WetHairAdvance)]),
    "wethair_sim_reset": (R, [vp]),
    "wethair_sim_get_vertex_layout": (R, [vp, P(S.WetHairVertexLayout)]),
    "wethair_sim_get_vertex_buffer": (R, [vp, f32p, C.c_size_t, P(C.c_size_t)]),
    "wethair_sim_get_water": (R, [vp, f32p, C.c_uint32, u32p]),
    "wethair_sim_get_stats": (R, [vp, P(S.WetHairStats)]),
    "wethair_sim_get_counters": (R, [vp, P(S.WetHairStats)]),
    "wethair_sim_get_backend_info": (R, [vp, P(S.WetHairBackendInfo)]),
    "wethair_sim_soak": (R, [vp, C.c_float]),
    "wethair_sim_set_wind": (R, [vp, P(S.WetHairWind)]),
    "wethair_sim_set_rain": (R, [vp, P(S.WetHairRain)]),
    "wethair_sim_set_spray": (R, [vp, P(S.WetHairSpray)]),
}


def library_path():
    """Where the library is loaded from (see the module's doc)."""
    env = os.environ.get("WETHAIR_LIBRARY")
    if env:
        return env
    name = _NAMES.get(sys.platform, "libwethair.so")
    beside = os.path.join(os.path.dirname(os.path.abspath(__file__)), name)
    if os.path.exists(beside):
        return beside
    found = ctypes.util.find_library("wethair")
    if found:
        return found
    raise ImportError(
        f"wethair: no {name} beside the package, no $WETHAIR_LIBRARY and none on the loader's path; "
        "install the wheel (bindings/python/README.md) or set WETHAIR_LIBRARY"
    )


def _load():
    lib = C.CDLL(library_path())
    for name, (res, args) in _PROTOTYPES.items():
        fn = getattr(lib, name)
        fn.restype = res
        fn.argtypes = args
    return lib


lib = _load()
