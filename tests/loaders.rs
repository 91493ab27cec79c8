//! Groom loaders: the real TressFX mohawk loads; every kind of malformed file is an error
//! (never a panic or an out-of-bounds read).

use std::path::PathBuf;
use wethair::groom::{load_cyhair, load_file, load_tfx};
use wethair::Error;

fn mohawk() -> Vec<u8> {
    std::fs::read(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/Ratboy_mohawk.tfx")).unwrap()
}

#[test]
fn mohawk_loads_as_2228_by_32() {
    let g = load_tfx(&mohawk(), 1e-3).unwrap();
    assert_eq!(g.strand_count(), 2228);
    assert_eq!(g.point_count(), 2228 * 32);
    assert_eq!(g.max_strand_points(), 32);
    // The first two vertices of every strand are fixed (w = 0) in this asset.
    for s in 0..2228 {
        let r = g.strand_range(s);
        assert!(g.pinned()[r.start] && g.pinned()[r.start + 1] && !g.pinned()[r.start + 2]);
    }
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/Ratboy_mohawk.tfx");
    assert_eq!(load_file(&path, 1e-3).unwrap(), g);
}

fn is_parse_error<T: std::fmt::Debug>(r: Result<T, Error>) -> bool {
    matches!(r, Err(Error::Parse(_)) | Err(Error::Capacity(_)))
}

#[test]
fn truncated_tfx_is_an_error_at_every_length() {
    let bytes = mohawk();
    // Every cut inside the header and the first strands, then coarser steps to the end.
    let mut cuts: Vec<usize> = (0..2000).collect();
    cuts.extend((2000..bytes.len()).step_by(997));
    cuts.push(bytes.len() - 1);
    for n in cuts {
        assert!(
            is_parse_error(load_tfx(&bytes[..n], 1e-3)),
            "truncated to {n} bytes was accepted"
        );
    }
}

#[test]
fn malformed_tfx_headers_are_errors() {
    let good = mohawk();
    let patch = |off: usize, v: u32| {
        let mut b = good.clone();
        b[off..off + 4].copy_from_slice(&v.to_le_bytes());
        b
    };
    let cases = [
        ("version NaN", patch(0, f32::NAN.to_bits())),
        ("version 0", patch(0, 0f32.to_bits())),
        ("zero strands", patch(4, 0)),
        ("huge strand count", patch(4, u32::MAX)),
        ("one vertex per strand", patch(8, 1)),
        ("too many vertices per strand", patch(8, 100_000)),
        ("offset into header", patch(12, 16)),
        ("offset past the end", patch(12, u32::MAX - 8)),
    ];
    for (what, bytes) in cases {
        assert!(is_parse_error(load_tfx(&bytes, 1e-3)), "{what} was accepted");
    }
    let mut nan = good.clone();
    nan[0xa0..0xa4].copy_from_slice(&f32::NAN.to_le_bytes());
    assert!(is_parse_error(load_tfx(&nan, 1e-3)), "NaN vertex accepted");
}

/// A small `.hair` file: 2 strands (3 and 4 points), segments array present.
fn hair_file(segments: &[u16], points: &[[f32; 3]], flags: u32) -> Vec<u8> {
    let mut b = Vec::new();
    b.extend_from_slice(b"HAIR");
    b.extend_from_slice(&(segments.len() as u32).to_le_bytes());
    b.extend_from_slice(&(points.len() as u32).to_le_bytes());
    b.extend_from_slice(&flags.to_le_bytes());
    b.extend_from_slice(&3u32.to_le_bytes()); // default segments
    b.resize(128, 0);
    if flags & 1 != 0 {
        segments.iter().for_each(|s| b.extend_from_slice(&s.to_le_bytes()));
    }
    points
        .iter()
        .flatten()
        .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    b
}

#[test]
fn cyhair_loads_and_rejects_malformed_files() {
    let pts: Vec<[f32; 3]> = (0..7).map(|i| [i as f32 * 0.01, 0.0, 0.0]).collect();
    let good = hair_file(&[2, 3], &pts, 0b11);
    let g = load_cyhair(&good, 1e-3).unwrap();
    assert_eq!((g.strand_count(), g.point_count()), (2, 7));
    assert_eq!(g.strand_range(1), 3..7);
    assert!(g.pinned()[0] && g.pinned()[3] && !g.pinned()[1]);
    // Default segment count (3) for every strand when the segments array is absent.
    let uniform = hair_file(&[3, 3], &(0..8).map(|i| [i as f32, 0.0, 0.0]).collect::<Vec<_>>(), 0b10);
    assert_eq!(load_cyhair(&uniform, 1e-3).unwrap().point_count(), 8);

    for n in 0..good.len() {
        assert!(
            is_parse_error(load_cyhair(&good[..n], 1e-3)),
            "truncated to {n} bytes was accepted"
        );
    }
    let mut bad_sig = good.clone();
    bad_sig[0] = b'X';
    assert!(is_parse_error(load_cyhair(&bad_sig, 1e-3)));
    assert!(
        is_parse_error(load_cyhair(&hair_file(&[2, 3], &pts, 0b01), 1e-3)),
        "no point array accepted"
    );
    assert!(
        is_parse_error(load_cyhair(&hair_file(&[2, 4], &pts, 0b11), 1e-3)),
        "segment sum mismatch accepted"
    );
    assert!(
        is_parse_error(load_cyhair(&hair_file(&[0, 5], &pts, 0b11), 1e-3)),
        "1-point strand accepted"
    );
    let mut nan = pts.clone();
    nan[4][1] = f32::INFINITY;
    assert!(
        is_parse_error(load_cyhair(&hair_file(&[2, 3], &nan, 0b11), 1e-3)),
        "inf point accepted"
    );
    let mut huge = good.clone();
    huge[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(is_parse_error(load_cyhair(&huge, 1e-3)));
}

#[test]
fn missing_file_and_unknown_format_are_errors() {
    assert!(matches!(
        load_file(std::path::Path::new("/nonexistent/x.tfx"), 1e-3),
        Err(Error::Io(_))
    ));
    let tmp = std::env::temp_dir().join(format!("wethair-{}.bin", std::process::id()));
    std::fs::write(&tmp, b"not a groom").unwrap();
    assert!(matches!(load_file(&tmp, 1e-3), Err(Error::Parse(_))));
    std::fs::remove_file(tmp).ok();
}

/// Random corruption never panics or reads out of bounds: every mutated file either loads
/// (a harmless change, e.g. in the UVs) or returns a parse/capacity error.
#[test]
fn corrupted_files_never_panic() {
    let good = mohawk();
    let mut seed = 0x2545_f491u32;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed
    };
    for _ in 0..400 {
        let mut b = good[..(next() as usize % good.len()).max(200)].to_vec();
        for _ in 0..(next() % 8) {
            // Hit the header most of the time: that is where the offsets and counts live.
            let at = if next() % 4 == 0 {
                next() as usize % b.len()
            } else {
                next() as usize % 160
            };
            b[at] = next() as u8;
        }
        match std::panic::catch_unwind(|| load_tfx(&b, 1e-3)) {
            Ok(Ok(g)) => assert!(g.positions().iter().all(|p| p.is_finite())),
            Ok(Err(e)) => assert!(matches!(e, Error::Parse(_) | Error::Capacity(_)), "{e}"),
            Err(_) => panic!("load_tfx panicked on a corrupted file"),
        }
        let mut h = b"HAIR".to_vec();
        h.extend((0..(next() % 400)).map(|_| next() as u8));
        assert!(
            std::panic::catch_unwind(|| load_cyhair(&h, 1e-3).map(|_| ())).is_ok(),
            "load_cyhair panicked"
        );
    }
}

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

/// Item 7: the TressFX 3.0 ponytail parts load (517 and 876 strands of 16 float3 points, roots
/// pinned); in centimetres and y up, the options make metres and z up.
#[test]
fn tressfx_3_files_load_and_options_make_metres_z_up() {
    use wethair::groom::{load_file_with, LoadOptions, UpAxis};
    for (name, strands) in [("ponytail_back.tfx", 517), ("ponytail_front_top.tfx", 876)] {
        let raw = load_file(&data(name), 1e-3).unwrap();
        assert_eq!(
            (raw.strand_count(), raw.point_count()),
            (strands, strands * 16),
            "{name}"
        );
        for s in 0..strands {
            let r = raw.strand_range(s);
            assert!(raw.pinned()[r.start] && !raw.pinned()[r.start + 1], "{name}: root only");
        }
        // Roots at y = 62-124 in the file (centimetres, y up).
        let roots: Vec<_> = (0..strands)
            .map(|s| raw.positions()[raw.strand_range(s).start])
            .collect();
        assert!(
            roots.iter().all(|p| (60.0..130.0).contains(&p.y)),
            "{name}: roots in cm, y up"
        );
        let opt = LoadOptions {
            scale: 0.01,
            up_axis: UpAxis::Y_TO_Z,
            ..Default::default()
        };
        let g = load_file_with(&data(name), &opt).unwrap();
        for (s, r) in roots.iter().enumerate() {
            let p = g.positions()[g.strand_range(s).start];
            assert!(
                (p - glam::Vec3::new(r.x, -r.z, r.y) * 0.01).length() < 1e-6,
                "{name}: strand {s}"
            );
            assert!((0.6..1.3).contains(&p.z), "{name}: root at {p} m, z up");
        }
        assert!(g.max_strand_length() < 1.0, "{name}: strands under a metre");
    }
}

/// Item 7: versions other than 3.x and 4.x are refused, naming the version found.
#[test]
fn tfx_versions_other_than_3_and_4_are_refused_by_name() {
    let mut b = std::fs::read(data("ponytail_back.tfx")).unwrap();
    for v in [2.0f32, 5.0, 1.0, 16.0] {
        b[0..4].copy_from_slice(&v.to_le_bytes());
        match load_tfx(&b, 1e-3) {
            Err(Error::Parse(m)) => assert!(m.contains(&format!("version {v}")) && m.contains("3.x and 4.x"), "{m}"),
            r => panic!("version {v}: {r:?}"),
        }
    }
    // A 3.0 file cut anywhere is an error, never a panic.
    let good = std::fs::read(data("ponytail_back.tfx")).unwrap();
    for n in (0..good.len()).step_by(97) {
        assert!(is_parse_error(load_tfx(&good[..n], 1e-3)), "cut at {n} accepted");
    }
}

/// A USC-HairSalon `.data` file: i32 strand count, then per strand an i32 point count and
/// that many float3.
fn usc_bytes(strands: &[Vec<[f32; 3]>]) -> Vec<u8> {
    let mut b = (strands.len() as i32).to_le_bytes().to_vec();
    for s in strands {
        b.extend((s.len() as i32).to_le_bytes());
        for p in s {
            for c in p {
                b.extend(c.to_le_bytes());
            }
        }
    }
    b
}

/// Item 9: USC-HairSalon `.data` files load (strands of fewer than 2 points are skipped);
/// malformed ones are errors.
#[test]
fn usc_hairsalon_data_files_load() {
    use wethair::groom::load_usc;
    let strands = vec![
        (0..5).map(|i| [0.0, 0.3 - 0.01 * i as f32, 0.0]).collect::<Vec<_>>(),
        vec![[0.1, 0.3, 0.0]], // a bald root
        vec![],
        (0..3).map(|i| [0.1, 0.3 - 0.02 * i as f32, 0.05]).collect(),
    ];
    let b = usc_bytes(&strands);
    let g = load_usc(&b, 1e-3).unwrap();
    assert_eq!((g.strand_count(), g.point_count()), (2, 8));
    assert_eq!(g.positions()[5], glam::Vec3::new(0.1, 0.3, 0.05));
    assert!(g.pinned()[0] && g.pinned()[5] && !g.pinned()[1]);
    // Through load_file by extension, with the options (y up to z up).
    let path = std::env::temp_dir().join(format!("wethair-test-{}.data", std::process::id()));
    std::fs::write(&path, &b).unwrap();
    let opt = wethair::groom::LoadOptions {
        up_axis: wethair::groom::UpAxis::Y_TO_Z,
        ..Default::default()
    };
    let z = wethair::groom::load_file_with(&path, &opt).unwrap();
    assert_eq!(z.positions()[5], glam::Vec3::new(0.1, -0.05, 0.3));
    std::fs::remove_file(&path).ok();
    // Malformed: cut anywhere, a negative count, trailing bytes, nothing simulable.
    for n in 0..b.len() {
        assert!(is_parse_error(load_usc(&b[..n], 1e-3)), "cut at {n} accepted");
    }
    let mut neg = b.clone();
    neg[4..8].copy_from_slice(&(-3i32).to_le_bytes());
    assert!(is_parse_error(load_usc(&neg, 1e-3)));
    let mut extra = b.clone();
    extra.push(0);
    assert!(is_parse_error(load_usc(&extra, 1e-3)));
    assert!(is_parse_error(load_usc(&usc_bytes(&[vec![[0.0; 3]]]), 1e-3)));
}

/// Item 8: the options: every Nth strand, resampling along the arc length (ends kept, evenly
/// spaced, the pinned prefix kept pinned), masses from a linear density, and bad values
/// refused by name.
#[test]
fn load_options_subsample_resample_and_weigh() {
    use wethair::groom::{LoadOptions, UpAxis};
    let raw = load_tfx(&mohawk(), 1e-3).unwrap();
    let every3 = LoadOptions {
        strand_stride: 3,
        weld_length: 0.0,
        ..Default::default()
    }
    .apply(&raw)
    .unwrap();
    assert_eq!(every3.strand_count(), 2228usize.div_ceil(3));
    assert_eq!(
        every3.positions()[every3.strand_range(1).start],
        raw.positions()[raw.strand_range(3).start]
    );

    let opt = LoadOptions {
        resample_points: 12,
        linear_density: 6e-5,
        weld_length: 0.0,
        ..Default::default()
    };
    let g = opt.apply(&raw).unwrap();
    assert_eq!((g.strand_count(), g.point_count()), (2228, 2228 * 12));
    let arc = |p: &[glam::Vec3]| p.windows(2).map(|w| (w[1] - w[0]).length()).sum::<f32>();
    for s in [0, 700, 2227] {
        let (a, b) = (&raw.positions()[raw.strand_range(s)], &g.positions()[g.strand_range(s)]);
        assert_eq!((a[0], a[31]), (b[0], b[11]), "strand {s}: ends kept");
        let (la, lb) = (arc(a), arc(b));
        assert!(lb <= la * 1.0001 && lb >= la * 0.95, "strand {s}: length {la} -> {lb}");
        let segs: Vec<f32> = b.windows(2).map(|w| (w[1] - w[0]).length()).collect();
        assert!(
            segs.iter().all(|&l| l <= la / 11.0 * 1.001),
            "strand {s}: evenly spaced {segs:?}"
        );
        // The root pinned; the masses are the density times the strand's length.
        assert!(g.pinned()[g.strand_range(s).start]);
        let m: f32 = g.masses()[g.strand_range(s)].iter().sum();
        assert!((m - 6e-5 * lb).abs() <= 1e-3 * m, "strand {s}: mass {m} for {lb} m");
    }
    for (bad, field) in [
        (
            LoadOptions {
                scale: 0.0,
                ..Default::default()
            },
            "scale",
        ),
        (
            LoadOptions {
                scale: f32::NAN,
                ..Default::default()
            },
            "scale",
        ),
        (
            LoadOptions {
                point_mass: -1.0,
                ..Default::default()
            },
            "point_mass",
        ),
        (
            LoadOptions {
                linear_density: f32::INFINITY,
                ..Default::default()
            },
            "linear_density",
        ),
        (
            LoadOptions {
                strand_stride: 0,
                ..Default::default()
            },
            "strand_stride",
        ),
        (
            LoadOptions {
                resample_points: 1,
                ..Default::default()
            },
            "resample_points",
        ),
        (
            LoadOptions {
                resample_points: 257,
                ..Default::default()
            },
            "resample_points",
        ),
    ] {
        match bad.apply(&raw) {
            Err(Error::InvalidArgument(m)) => assert!(m.contains(field), "{m}"),
            r => panic!("{field}: {:?}", r.map(|g| g.point_count())),
        }
    }
    assert_eq!(UpAxis::default(), UpAxis::KEEP);
}
