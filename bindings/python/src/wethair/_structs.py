"""ctypes mirrors of the C header's structs (``include/wethair.h``), field for field.

The header is the source of truth: ``tests/test_layout.py`` compiles a C program that prints
every struct's ``sizeof`` and every field's ``offsetof`` and compares them with these (the
same check the C# bindings pass), so a field added to the header and not here fails CI.
"""

import ctypes as C

f32, u8, u32, i32, u64 = C.c_float, C.c_uint8, C.c_uint32, C.c_int32, C.c_uint64


class WetHairGroomDesc(C.Structure):
    """Strands given by the host (``wethair_groom_create``)."""

    _fields_ = [
        ("struct_size", u32),
        ("strand_count", u32),
        ("strand_point_counts", C.POINTER(u32)),
        ("positions", C.POINTER(f32)),
        ("point_count", u32),
        ("pinned", C.POINTER(u8)),
        ("masses", C.POINTER(f32)),
        ("default_mass", f32),
    ]


class WetHairLoadDesc(C.Structure):
    """How a groom file is brought into metres (``wethair_groom_load_with_desc``)."""

    _fields_ = [
        ("struct_size", u32),
        ("scale", f32),
        ("up_axis", u32),
        ("point_mass", f32),
        ("linear_density", f32),
        ("strand_stride", u32),
        ("resample_points", u32),
        ("weld_length", f32),
    ]


class WetHairSpring(C.Structure):
    _fields_ = [("stiffness", f32), ("damping", f32)]


class WetHairWaterDesc(C.Structure):
    _fields_ = [
        ("r_min", f32),
        ("r_max", f32),
        ("adhesion", f32),
        ("particle_mass", f32),
        ("drag", f32),
        ("capacity", u32),
        ("wetting_rate", f32),
        ("domain_radius", f32),
    ]


class WetHairCollider(C.Structure):
    _fields_ = [("shape", u32), ("a", f32 * 3), ("b", f32 * 3), ("radius", f32)]


class WetHairMaterial(C.Structure):
    _fields_ = [
        ("stretch_modulus", f32),
        ("stretch_damping", f32),
        ("bend_modulus", f32),
        ("bend_damping", f32),
    ]


class WetHairHeldWater(C.Structure):
    _fields_ = [
        ("enabled", u32),
        ("capacity_ratio", f32),
        ("dry_time", f32),
        ("dry_air_speed", f32),
        ("absorb_rate", f32),
        ("wet_bend_ratio", f32),
        ("bridge_tension", f32),
        ("bridge_length", f32),
        ("flow_mobility", f32),
        ("drip_mass", f32),
    ]


class WetHairWind(C.Structure):
    _fields_ = [("velocity", f32 * 3), ("gust", f32), ("seed", u32)]


class WetHairSdf(C.Structure):
    _fields_ = [
        ("dims", u32 * 3),
        ("origin", f32 * 3),
        ("cell_size", f32),
        ("reserved", u32),
        ("values", C.POINTER(f32)),
        ("transform", f32 * 16),
    ]


class WetHairVolume(C.Structure):
    _fields_ = [
        ("enabled", u32),
        ("cell", f32),
        ("pressure", f32),
        ("friction", f32),
        ("rest_density", f32),
        ("reserved", u32),
    ]


class WetHairGuides(C.Structure):
    _fields_ = [
        ("choice", u32),
        ("count", u32),
        ("strands", C.POINTER(u32)),
        ("per_follower", u32),
        ("clump", f32),
        ("fraction", f32),
        ("blend_time", f32),
    ]


class WetHairSimDesc(C.Structure):
    """Everything a simulation is made from; filled by ``wethair_sim_desc_init``."""

    _fields_ = [
        ("struct_size", u32),
        ("damping_model", u32),
        ("groom", C.c_void_p),
        ("stretch", WetHairSpring),
        ("bend", WetHairSpring),
        ("gravity", f32 * 3),
        ("air_drag", f32),
        ("substeps", u32),
        ("integrator", u32),
        ("solver_iterations", u32),
        ("threads", u32),
        ("water", WetHairWaterDesc),
        ("colliders", C.POINTER(WetHairCollider)),
        ("collider_count", u32),
        ("friction", f32),
        ("vertex_attributes", u32),
        ("backend", u32),
        ("readback", u32),
        ("reserved", u32),
        ("spring_model", u32),
        ("material", WetHairMaterial),
        ("reserved2", u32),
        ("held_water", WetHairHeldWater),
        ("wind", WetHairWind),
        ("reserved3", u32),
        ("error_estimate_stride", u32),
        ("tolerance", f32),
        ("max_substeps", u32),
        ("reserved4", u32),
        ("fixed_step", f32),
        ("max_frame_time", f32),
        ("interpolate", u32),
        ("reserved5", u32),
        ("sdfs", C.POINTER(WetHairSdf)),
        ("sdf_count", u32),
        ("reserved6", u32),
        ("skinned_roots", u32),
        ("root_teleport_distance", f32),
        ("volume", WetHairVolume),
        ("guides", WetHairGuides),
        ("held_water_free_ratio", f32),
        ("reserved7", u32),
        ("held_water_flow_length", f32),
        ("reserved8", u32),
        ("air_drag_length", f32),
        ("reserved9", u32),
        ("water_adhesion_length", f32),
        ("reserved10", u32),
        ("water_pile_cell", f32),
        ("reserved11", u32),
        ("collider_frames", C.POINTER(f32)),
    ]


class WetHairAdvance(C.Structure):
    _fields_ = [("struct_size", u32), ("steps", u32), ("blend", f32), ("dropped_time", f32)]


class WetHairVertexLayout(C.Structure):
    _fields_ = [
        ("struct_size", u32),
        ("vertex_count", u32),
        ("strand_count", u32),
        ("stride_floats", u32),
        ("position_offset", i32),
        ("tangent_offset", i32),
        ("wetness_offset", i32),
    ]


class WetHairStats(C.Structure):
    _fields_ = [
        ("struct_size", u32),
        ("strands", u32),
        ("points", u32),
        ("particles", u32),
        ("particles_removed", u64),
        ("steps", u64),
        ("last_step_ms", f32),
        ("max_speed", f32),
        ("clumping", f32),
        ("threads", u32),
        ("integrator", u32),
        ("backend", u32),
        ("clumping_along", f32),
        ("water_added", u64),
        ("water_in_particles", u64),
        ("water_held", u64),
        ("water_left", u64),
        ("water_evaporated", u64),
        ("error_estimate", f32),
        ("error_estimate_max", f32),
        ("substeps", u32),
        ("reserved", u32),
    ]


class WetHairBackendInfo(C.Structure):
    _fields_ = [
        ("struct_size", u32),
        ("backend", u32),
        ("device", C.c_char * 128),
        ("fallback_reason", C.c_char * 256),
    ]


class WetHairRain(C.Structure):
    _fields_ = [("center", f32 * 3), ("size", f32 * 2), ("rate", f32), ("speed", f32), ("seed", u32)]


class WetHairSpray(C.Structure):
    _fields_ = [
        ("origin", f32 * 3),
        ("direction", f32 * 3),
        ("half_angle", f32),
        ("rate", f32),
        ("speed", f32),
        ("seed", u32),
    ]


#: Every mirrored struct, for the layout check against the header.
ALL = [
    WetHairGroomDesc,
    WetHairLoadDesc,
    WetHairSpring,
    WetHairWaterDesc,
    WetHairCollider,
    WetHairMaterial,
    WetHairHeldWater,
    WetHairWind,
    WetHairSdf,
    WetHairVolume,
    WetHairGuides,
    WetHairSimDesc,
    WetHairAdvance,
    WetHairVertexLayout,
    WetHairStats,
    WetHairBackendInfo,
    WetHairRain,
    WetHairSpray,
]


def layout_lines():
    """``size T N`` and ``offset T field N`` lines, the format ``check_layout.sh`` compares."""
    out = []
    for ty in ALL:
        out.append(f"size {ty.__name__} {C.sizeof(ty)}")
        for name, _ in ty._fields_:
            out.append(f"offset {ty.__name__} {name} {getattr(ty, name).offset}")
    return out
