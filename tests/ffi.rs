//! The C ABI: every entry point given NULL, NaN, a negative or huge count, an unknown enum or
//! a wrong struct_size returns its documented error, sets a message, and writes nothing.

use std::ffi::CStr;
use std::ptr::{null, null_mut};
use wethair::ffi::*;
use WetHairResult::*;

const SENTINEL: *mut WetHairGroom = 0x5a5a as *mut WetHairGroom;

use crate::common::last_error;

fn paper(strands: u32) -> *mut WetHairGroom {
    let mut g = null_mut();
    assert_eq!(
        unsafe { wethair_groom_create_paper_scene(strands, 6, &mut g) },
        WETHAIR_OK
    );
    g
}

fn desc(groom: *const WetHairGroom) -> WetHairSimDesc {
    let mut d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed();
    unsafe {
        wethair_sim_desc_default(d.as_mut_ptr());
        let mut d = d.assume_init();
        d.groom = groom;
        d
    }
}

fn sim(strands: u32) -> (*mut WetHairGroom, *mut WetHairSim) {
    let g = paper(strands);
    let mut s = null_mut();
    assert_eq!(unsafe { wethair_sim_create(&desc(g), &mut s) }, WETHAIR_OK);
    (g, s)
}

/// Checks the code, that a message was set, and that `out` kept its sentinel.
fn expect_sim_create_fails(d: &WetHairSimDesc, code: WetHairResult, what: &str) {
    let mut out = SENTINEL as *mut WetHairSim;
    let r = unsafe { wethair_sim_create(d, &mut out) };
    assert_eq!(r, code, "{what}: {}", last_error());
    assert_eq!(out, SENTINEL as *mut WetHairSim, "{what}: output written on failure");
    assert!(!last_error().is_empty());
}

#[test]
fn meta_functions() {
    assert_eq!(wethair_version(), 100);
    let v = unsafe { CStr::from_ptr(wethair_version_string()) };
    assert_eq!(v.to_str().unwrap(), env!("CARGO_PKG_VERSION"));
    let name = |r: u32| {
        unsafe { CStr::from_ptr(wethair_result_string(r)) }
            .to_str()
            .unwrap()
            .to_owned()
    };
    assert_eq!(name(0), "WETHAIR_OK");
    assert_eq!(name(8), "WETHAIR_ERROR_UNSTABLE");
    assert_eq!(name(12345), "WETHAIR_RESULT_UNKNOWN");
    unsafe {
        wethair_sim_desc_default(null_mut());
        wethair_groom_desc_default(null_mut());
        wethair_sim_destroy(null_mut());
        wethair_groom_destroy(null_mut());
    }
}

#[test]
fn groom_create_checks_everything() {
    let pos = [0.0f32, 0.0, 0.0, 0.0, 0.0, -0.02, 0.0, 0.0, -0.04];
    let counts = [3u32];
    let mut d = std::mem::MaybeUninit::<WetHairGroomDesc>::zeroed();
    let base = unsafe {
        wethair_groom_desc_default(d.as_mut_ptr());
        let mut d = d.assume_init();
        d.positions = pos.as_ptr();
        d.point_count = 3;
        d.strand_point_counts = counts.as_ptr();
        d.strand_count = 1;
        d
    };
    let mut g = null_mut();
    assert_eq!(unsafe { wethair_groom_create(&base, &mut g) }, WETHAIR_OK);
    let (mut s, mut p) = (0, 0);
    assert_eq!(unsafe { wethair_groom_get_counts(g, &mut s, &mut p) }, WETHAIR_OK);
    assert_eq!((s, p), (1, 3));
    unsafe { wethair_groom_destroy(g) };

    let nan = [0.0f32, 0.0, 0.0, f32::NAN, 0.0, -0.02, 0.0, 0.0, -0.04];
    let cases: Vec<(WetHairGroomDesc, WetHairResult, &str)> = vec![
        (
            WetHairGroomDesc { struct_size: 4, ..base },
            WETHAIR_ERROR_STRUCT_SIZE,
            "struct_size",
        ),
        (
            WetHairGroomDesc {
                positions: null(),
                ..base
            },
            WETHAIR_ERROR_NULL_POINTER,
            "NULL positions",
        ),
        (
            WetHairGroomDesc {
                strand_point_counts: null(),
                ..base
            },
            WETHAIR_ERROR_NULL_POINTER,
            "NULL counts",
        ),
        (
            WetHairGroomDesc {
                positions: nan.as_ptr(),
                ..base
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "NaN position",
        ),
        (
            WetHairGroomDesc { point_count: 2, ..base },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "count mismatch",
        ),
        (
            WetHairGroomDesc {
                strand_count: u32::MAX,
                ..base
            },
            WETHAIR_ERROR_CAPACITY,
            "huge strand count",
        ),
        (
            WetHairGroomDesc {
                point_count: u32::MAX,
                ..base
            },
            WETHAIR_ERROR_CAPACITY,
            "huge point count",
        ),
        (
            WetHairGroomDesc {
                strand_count: 0,
                ..base
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "no strands",
        ),
        (
            WetHairGroomDesc {
                default_mass: -1.0,
                ..base
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "negative mass",
        ),
        (
            WetHairGroomDesc {
                default_mass: f32::NAN,
                ..base
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "NaN mass",
        ),
    ];
    for (d, code, what) in cases {
        let mut out = SENTINEL;
        assert_eq!(
            unsafe { wethair_groom_create(&d, &mut out) },
            code,
            "{what}: {}",
            last_error()
        );
        assert_eq!(out, SENTINEL, "{what}: output written on failure");
    }
    assert_eq!(
        unsafe { wethair_groom_create(null(), &mut g) },
        WETHAIR_ERROR_NULL_POINTER
    );
    assert_eq!(
        unsafe { wethair_groom_create(&base, null_mut()) },
        WETHAIR_ERROR_NULL_POINTER
    );
    assert_eq!(
        unsafe { wethair_groom_get_counts(null(), &mut s, &mut p) },
        WETHAIR_ERROR_NULL_POINTER
    );
}

#[test]
fn groom_paper_and_load_check_everything() {
    let mut out = SENTINEL;
    unsafe {
        assert_eq!(
            wethair_groom_create_paper_scene(10, 6, null_mut()),
            WETHAIR_ERROR_NULL_POINTER
        );
        assert_eq!(
            wethair_groom_create_paper_scene(0, 6, &mut out),
            WETHAIR_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            wethair_groom_create_paper_scene(10, 1, &mut out),
            WETHAIR_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            wethair_groom_create_paper_scene(u32::MAX, u32::MAX, &mut out),
            WETHAIR_ERROR_CAPACITY
        );
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/Ratboy_mohawk.tfx\0")
            .as_ptr()
            .cast();
        assert_eq!(wethair_groom_load(null(), 1e-3, &mut out), WETHAIR_ERROR_NULL_POINTER);
        assert_eq!(
            wethair_groom_load(path, f32::NAN, &mut out),
            WETHAIR_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(wethair_groom_load(path, -1.0, &mut out), WETHAIR_ERROR_INVALID_ARGUMENT);
        assert_eq!(
            wethair_groom_load(c"/nonexistent.tfx".as_ptr(), 1e-3, &mut out),
            WETHAIR_ERROR_IO
        );
        let cargo = concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml\0").as_ptr().cast();
        assert_eq!(wethair_groom_load(cargo, 1e-3, &mut out), WETHAIR_ERROR_PARSE);
        assert_eq!(out, SENTINEL);
        assert_eq!(wethair_groom_load(path, 1e-3, &mut out), WETHAIR_OK);
        let (mut s, mut p) = (0, 0);
        wethair_groom_get_counts(out, &mut s, &mut p);
        assert_eq!((s, p), (2228, 2228 * 32));
        wethair_groom_destroy(out);
    }
}

#[test]
fn sim_create_checks_every_field() {
    let g = paper(100);
    let good = desc(g);
    let sphere = WetHairCollider {
        shape: 0,
        a: [0.0; 3],
        b: [0.0; 3],
        radius: 0.1,
    };
    let bad_type = WetHairCollider { shape: 9, ..sphere };
    let bad_radius = WetHairCollider {
        radius: f32::NAN,
        ..sphere
    };
    let w = good.water;
    let cases: Vec<(WetHairSimDesc, WetHairResult, &str)> = vec![
        (
            WetHairSimDesc { struct_size: 8, ..good },
            WETHAIR_ERROR_STRUCT_SIZE,
            "struct_size",
        ),
        (
            WetHairSimDesc {
                struct_size: u32::MAX,
                ..good
            },
            WETHAIR_ERROR_STRUCT_SIZE,
            "struct_size huge",
        ),
        (
            WetHairSimDesc { groom: null(), ..good },
            WETHAIR_ERROR_NULL_POINTER,
            "NULL groom",
        ),
        (
            WetHairSimDesc {
                damping_model: 7,
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "damping enum",
        ),
        (
            WetHairSimDesc {
                stretch: WetHairSpring {
                    stiffness: f32::NAN,
                    damping: 0.0,
                },
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "NaN k",
        ),
        (
            WetHairSimDesc {
                stretch: WetHairSpring {
                    stiffness: f32::INFINITY,
                    damping: 0.0,
                },
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "inf k",
        ),
        (
            WetHairSimDesc {
                bend: WetHairSpring {
                    stiffness: 1.0,
                    damping: -1.0,
                },
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "negative c",
        ),
        (
            WetHairSimDesc {
                gravity: [0.0, f32::NAN, 0.0],
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "NaN gravity",
        ),
        (
            WetHairSimDesc { air_drag: -0.1, ..good },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "negative drag",
        ),
        (
            WetHairSimDesc { substeps: 0, ..good },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "0 substeps",
        ),
        (
            WetHairSimDesc {
                substeps: 100_000,
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "huge substeps",
        ),
        (
            WetHairSimDesc {
                threads: 100_000,
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "huge threads",
        ),
        (
            WetHairSimDesc {
                water: WetHairWaterDesc { r_max: 0.001, ..w },
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "r_max <= r_min",
        ),
        (
            WetHairSimDesc {
                water: WetHairWaterDesc { r_min: -0.001, ..w },
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "negative r_min",
        ),
        (
            WetHairSimDesc {
                water: WetHairWaterDesc {
                    adhesion: f32::NAN,
                    ..w
                },
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "NaN adhesion",
        ),
        (
            WetHairSimDesc {
                water: WetHairWaterDesc {
                    particle_mass: 0.0,
                    ..w
                },
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "zero particle mass",
        ),
        (
            WetHairSimDesc {
                water: WetHairWaterDesc {
                    capacity: u32::MAX,
                    ..w
                },
                ..good
            },
            WETHAIR_ERROR_CAPACITY,
            "huge capacity",
        ),
        (
            WetHairSimDesc {
                collider_count: 1,
                colliders: null(),
                ..good
            },
            WETHAIR_ERROR_NULL_POINTER,
            "NULL colliders",
        ),
        (
            WetHairSimDesc {
                collider_count: 1000,
                colliders: &sphere,
                ..good
            },
            WETHAIR_ERROR_CAPACITY,
            "huge collider count",
        ),
        (
            WetHairSimDesc {
                collider_count: 1,
                colliders: &bad_type,
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "collider enum",
        ),
        (
            WetHairSimDesc {
                collider_count: 1,
                colliders: &bad_radius,
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "NaN radius",
        ),
        (
            WetHairSimDesc { friction: 2.0, ..good },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "friction > 1",
        ),
        (
            WetHairSimDesc {
                vertex_attributes: 0,
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "no attributes",
        ),
        (
            WetHairSimDesc {
                vertex_attributes: 8,
                ..good
            },
            WETHAIR_ERROR_INVALID_ARGUMENT,
            "unknown attribute",
        ),
    ];
    for (d, code, what) in cases {
        expect_sim_create_fails(&d, code, what);
    }
    let mut out = null_mut();
    assert_eq!(
        unsafe { wethair_sim_create(null(), &mut out) },
        WETHAIR_ERROR_NULL_POINTER
    );
    assert_eq!(
        unsafe { wethair_sim_create(&good, null_mut()) },
        WETHAIR_ERROR_NULL_POINTER
    );
    let with_head = WetHairSimDesc {
        collider_count: 1,
        colliders: &sphere,
        ..good
    };
    assert_eq!(unsafe { wethair_sim_create(&with_head, &mut out) }, WETHAIR_OK);
    unsafe {
        wethair_sim_destroy(out);
        wethair_groom_destroy(g);
    }
}

#[test]
fn sim_calls_check_everything_and_write_nothing_on_failure() {
    let (g, s) = sim(50);
    unsafe {
        // Head transform.
        let mut m = [0.0f32; 16];
        for i in 0..4 {
            m[i * 5] = 1.0;
        }
        assert_eq!(
            wethair_sim_set_head_transform(null_mut(), m.as_ptr()),
            WETHAIR_ERROR_NULL_POINTER
        );
        assert_eq!(wethair_sim_set_head_transform(s, null()), WETHAIR_ERROR_NULL_POINTER);
        let mut bad = m;
        bad[5] = f32::NAN;
        assert_eq!(
            wethair_sim_set_head_transform(s, bad.as_ptr()),
            WETHAIR_ERROR_INVALID_ARGUMENT
        );
        let mut singular = m;
        singular[0] = 0.0;
        assert_eq!(
            wethair_sim_set_head_transform(s, singular.as_ptr()),
            WETHAIR_ERROR_INVALID_ARGUMENT
        );
        let mut projective = m;
        projective[3] = 0.5;
        assert_eq!(
            wethair_sim_set_head_transform(s, projective.as_ptr()),
            WETHAIR_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(wethair_sim_set_head_transform(s, m.as_ptr()), WETHAIR_OK);

        // Water: all or nothing.
        let p = [0.0f32, 0.0, 0.2, 0.01, 0.0, 0.2];
        let nanp = [0.0f32, 0.0, 0.2, f32::NAN, 0.0, 0.2];
        let infv = [0.0f32, 0.0, 0.0, 0.0, f32::INFINITY, 0.0];
        assert_eq!(
            wethair_sim_add_water(null_mut(), p.as_ptr(), null(), 2),
            WETHAIR_ERROR_NULL_POINTER
        );
        assert_eq!(wethair_sim_add_water(s, null(), null(), 2), WETHAIR_ERROR_NULL_POINTER);
        assert_eq!(
            wethair_sim_add_water(s, nanp.as_ptr(), null(), 2),
            WETHAIR_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            wethair_sim_add_water(s, p.as_ptr(), infv.as_ptr(), 2),
            WETHAIR_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            wethair_sim_add_water(s, p.as_ptr(), null(), u32::MAX),
            WETHAIR_ERROR_CAPACITY
        );
        let many = vec![0.1f32; 3 * 70_000];
        assert_eq!(
            wethair_sim_add_water(s, many.as_ptr(), null(), 70_000),
            WETHAIR_ERROR_CAPACITY
        );
        let mut stats: WetHairStats = std::mem::zeroed();
        stats.struct_size = std::mem::size_of::<WetHairStats>() as u32;
        assert_eq!(wethair_sim_get_stats(s, &mut stats), WETHAIR_OK);
        assert_eq!(stats.particles, 0, "a failed add_water added particles");
        assert_eq!(wethair_sim_add_water(s, p.as_ptr(), null(), 0), WETHAIR_OK);
        assert_eq!(wethair_sim_add_water(s, p.as_ptr(), null(), 2), WETHAIR_OK);
        assert_eq!(wethair_sim_clear_water(null_mut()), WETHAIR_ERROR_NULL_POINTER);

        // Step.
        for dt in [f32::NAN, f32::INFINITY, -1.0 / 60.0, 0.0, 2.0] {
            assert_eq!(wethair_sim_step(s, dt), WETHAIR_ERROR_INVALID_ARGUMENT, "dt {dt}");
        }
        assert_eq!(wethair_sim_step(null_mut(), 0.01), WETHAIR_ERROR_NULL_POINTER);
        assert_eq!(wethair_sim_step(s, 1.0 / 60.0), WETHAIR_OK);
        assert_eq!(wethair_sim_reset(null_mut()), WETHAIR_ERROR_NULL_POINTER);

        // Layout and stats: output struct_size checked, nothing written on failure.
        let mut layout = WetHairVertexLayout {
            struct_size: 3,
            vertex_count: 77,
            ..Default::default()
        };
        assert_eq!(wethair_sim_get_vertex_layout(s, &mut layout), WETHAIR_ERROR_STRUCT_SIZE);
        assert_eq!(layout.vertex_count, 77);
        assert_eq!(wethair_sim_get_vertex_layout(s, null_mut()), WETHAIR_ERROR_NULL_POINTER);
        assert_eq!(
            wethair_sim_get_vertex_layout(null(), &mut layout),
            WETHAIR_ERROR_NULL_POINTER
        );
        layout.struct_size = std::mem::size_of::<WetHairVertexLayout>() as u32;
        assert_eq!(wethair_sim_get_vertex_layout(s, &mut layout), WETHAIR_OK);
        assert_eq!((layout.vertex_count, layout.stride_floats), (300, 7));
        assert_eq!(
            (layout.position_offset, layout.tangent_offset, layout.wetness_offset),
            (0, 12, 24)
        );
        let mut st = WetHairStats {
            struct_size: 1,
            steps: 99,
            ..Default::default()
        };
        assert_eq!(wethair_sim_get_stats(s, &mut st), WETHAIR_ERROR_STRUCT_SIZE);
        assert_eq!(st.steps, 99);
        assert_eq!(wethair_sim_get_stats(null(), &mut st), WETHAIR_ERROR_NULL_POINTER);
        assert_eq!(wethair_sim_get_counters(s, &mut st), WETHAIR_ERROR_STRUCT_SIZE);
        assert_eq!(st.steps, 99);
        assert_eq!(wethair_sim_get_counters(null(), &mut st), WETHAIR_ERROR_NULL_POINTER);
        assert_eq!(wethair_sim_get_counters(s, null_mut()), WETHAIR_ERROR_NULL_POINTER);

        // Vertex buffer: too small or NULL writes nothing, `written` included.
        let need = 300 * 7;
        let mut buf = vec![-7.0f32; need];
        let mut written = 12345usize;
        assert_eq!(
            wethair_sim_get_vertex_buffer(s, buf.as_mut_ptr(), need - 1, &mut written),
            WETHAIR_ERROR_BUFFER_TOO_SMALL
        );
        assert!(buf.iter().all(|&v| v == -7.0) && written == 12345);
        assert_eq!(
            wethair_sim_get_vertex_buffer(s, null_mut(), need, &mut written),
            WETHAIR_ERROR_NULL_POINTER
        );
        assert_eq!(
            wethair_sim_get_vertex_buffer(s, buf.as_mut_ptr(), need, null_mut()),
            WETHAIR_ERROR_NULL_POINTER
        );
        assert_eq!(
            wethair_sim_get_vertex_buffer(null_mut(), buf.as_mut_ptr(), need, &mut written),
            WETHAIR_ERROR_NULL_POINTER
        );
        assert_eq!(
            wethair_sim_get_vertex_buffer(s, buf.as_mut_ptr(), need, &mut written),
            WETHAIR_OK
        );
        assert_eq!(written, need);
        assert!(buf.iter().all(|v| v.is_finite()));

        // Water read-back.
        let mut w = [0.0f32; 6];
        let mut n = 9u32;
        assert_eq!(
            wethair_sim_get_water(s, w.as_mut_ptr(), 2, null_mut()),
            WETHAIR_ERROR_NULL_POINTER
        );
        assert_eq!(
            wethair_sim_get_water(s, null_mut(), 2, &mut n),
            WETHAIR_ERROR_NULL_POINTER
        );
        assert_eq!(n, 9);
        // A buffer shorter than the particles held is refused, as a short vertex buffer is,
        // and nothing is written.
        let mut stats = WetHairStats {
            struct_size: std::mem::size_of::<WetHairStats>() as u32,
            ..Default::default()
        };
        assert_eq!(wethair_sim_get_stats(s, &mut stats), WETHAIR_OK);
        assert!(
            stats.particles >= 2,
            "the scene holds more particles than the short buffer"
        );
        assert_eq!(
            wethair_sim_get_water(s, w.as_mut_ptr(), stats.particles - 1, &mut n),
            WETHAIR_ERROR_BUFFER_TOO_SMALL
        );
        assert_eq!((n, w), (9, [0.0; 6]));
        let mut all = vec![0.0f32; 3 * stats.particles as usize];
        assert_eq!(
            wethair_sim_get_water(s, all.as_mut_ptr(), stats.particles, &mut n),
            WETHAIR_OK
        );
        assert_eq!(n, stats.particles);
        assert!(all.iter().all(|v| v.is_finite()));
        wethair_sim_destroy(s);
        wethair_groom_destroy(g);
    }
}

/// A step that diverges returns WETHAIR_ERROR_UNSTABLE naming the strand, keeps returning it,
/// gives no vertices, and reset brings the simulation back.
#[test]
fn unstable_step_is_reported_and_reset_recovers() {
    let g = paper(64);
    let mut d = desc(g);
    d.stretch.stiffness = 1.0e7;
    d.substeps = 1;
    let mut s = null_mut();
    unsafe {
        assert_eq!(wethair_sim_create(&d, &mut s), WETHAIR_OK);
        let mut r = WETHAIR_OK;
        for _ in 0..50 {
            r = wethair_sim_step(s, 1.0 / 30.0);
            if r != WETHAIR_OK {
                break;
            }
        }
        assert_eq!(r, WETHAIR_ERROR_UNSTABLE);
        assert!(last_error().contains("strand"), "{}", last_error());
        assert_eq!(wethair_sim_step(s, 1.0 / 30.0), WETHAIR_ERROR_UNSTABLE);
        let mut buf = vec![-7.0f32; 64 * 6 * 7];
        let mut written = 5usize;
        assert_eq!(
            wethair_sim_get_vertex_buffer(s, buf.as_mut_ptr(), buf.len(), &mut written),
            WETHAIR_ERROR_UNSTABLE
        );
        assert!(
            buf.iter().all(|&v| v == -7.0) && written == 5,
            "no NaN may reach the vertex buffer"
        );
        assert_eq!(wethair_sim_reset(s), WETHAIR_OK);
        assert_eq!(
            wethair_sim_get_vertex_buffer(s, buf.as_mut_ptr(), buf.len(), &mut written),
            WETHAIR_OK
        );
        assert!(buf.iter().all(|v| v.is_finite()));
        wethair_sim_destroy(s);
        wethair_groom_destroy(g);
    }
}

/// Only the requested attributes are written, in the documented order.
#[test]
fn vertex_attributes_select_the_layout() {
    let g = paper(10);
    for (bits, stride, offs) in [
        (1u32, 3u32, (0, -1, -1)),
        (4, 1, (-1, -1, 0)),
        (6, 4, (-1, 0, 12)),
        (5, 4, (0, -1, 12)),
    ] {
        let mut d = desc(g);
        d.vertex_attributes = bits;
        let mut s = null_mut();
        unsafe {
            assert_eq!(wethair_sim_create(&d, &mut s), WETHAIR_OK);
            let mut l = WetHairVertexLayout {
                struct_size: std::mem::size_of::<WetHairVertexLayout>() as u32,
                ..Default::default()
            };
            assert_eq!(wethair_sim_get_vertex_layout(s, &mut l), WETHAIR_OK);
            assert_eq!(l.stride_floats, stride);
            assert_eq!((l.position_offset, l.tangent_offset, l.wetness_offset), offs);
            let mut buf = vec![0.0f32; 60 * stride as usize];
            let mut n = 0;
            assert_eq!(
                wethair_sim_get_vertex_buffer(s, buf.as_mut_ptr(), buf.len(), &mut n),
                WETHAIR_OK
            );
            assert_eq!(n, buf.len());
            if offs.0 == 0 {
                // First vertex is strand 0's root at 0.1 m from the origin.
                let r = (buf[0] * buf[0] + buf[1] * buf[1] + buf[2] * buf[2]).sqrt();
                assert!((r - 0.1).abs() < 1e-6);
            }
            wethair_sim_destroy(s);
        }
    }
    unsafe { wethair_groom_destroy(g) };
}
