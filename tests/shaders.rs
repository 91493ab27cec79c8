//! The render-side shaders shipped in `bindings/shaders/` for engines: the WGSL one parses and
//! validates with naga (wgpu's shader compiler), and declares the vertex inputs the vertex
//! buffer provides. (GLSL and HLSL are compiled by glslang in `scripts/test.sh`.)
#![cfg(feature = "gpu")]

use wgpu::naga;

#[test]
fn kajiya_kay_wgsl_validates_with_the_vertex_layout() {
    let src = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/bindings/shaders/kajiya_kay.wgsl"))
        .expect("read kajiya_kay.wgsl");
    let module = naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&src)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{e:?}"));
    let names: Vec<&str> = module.entry_points.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(names, ["vs_main", "fs_main"]);
    // Locations 0, 1, 2: position (vec3), tangent (vec3), wetness (f32), as the buffer holds them.
    let vs = &module.entry_points[0].function;
    let arg = &module.types[vs.arguments[0].ty];
    let naga::TypeInner::Struct { members, .. } = &arg.inner else {
        panic!("vs_main takes a struct")
    };
    let locs: Vec<Option<u32>> = members
        .iter()
        .map(|m| match m.binding {
            Some(naga::Binding::Location { location, .. }) => Some(location),
            _ => None,
        })
        .collect();
    assert_eq!(locs, [Some(0), Some(1), Some(2)]);
}

/// The simulation's own output modules (vertices, shared water) validate with naga for a scene
/// with and without bend springs and colliders, before any device compiles them.
#[test]
fn output_modules_validate() {
    use wethair::gpu::pipelines::{
        held_source, output_source, sdf_hair_source, sdf_water_source, water_output_source, water_source,
    };
    for (bend, colliders) in [(false, 0), (true, 2)] {
        let c = consts(bend, colliders);
        for (name, src, entry) in [
            ("output", output_source(c), "write_vertices"),
            ("output", output_source(c), "write_vertices_blended"),
            (
                "guide frames",
                wethair::gpu::pipelines::guide_frames_source(c),
                "guide_frames",
            ),
            (
                "followers",
                wethair::gpu::pipelines::write_followers_source(c),
                "write_followers",
            ),
            ("water", water_source(c), "water_cull"),
            ("piles", wethair::gpu::pipelines::piles_source(c), "pile_insert"),
            ("water output", water_output_source(c), "write_water_vertices"),
            ("held", held_source(c, 1000), "dry"),
            ("sdf hair", sdf_hair_source(c, 3), "hair_sdf"),
            ("sdf water", sdf_water_source(c, 1), "water_sdf"),
        ] {
            let module =
                naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
            naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities(&src))
                .validate(&module)
                .unwrap_or_else(|e| panic!("{name}: {e:?}"));
            assert!(
                module.entry_points.iter().any(|e| e.name == entry),
                "{name} has no {entry}"
            );
        }
    }
}

/// What a module may use beyond core WGSL: 64-bit integers and their atomics in the modules
/// that add the particles' reactions that way (reaction64.wgsl, chosen only where the device
/// offers both), nothing elsewhere.
fn capabilities(src: &str) -> naga::valid::Capabilities {
    if src.contains("atomic<u64>") {
        naga::valid::Capabilities::SHADER_INT64 | naga::valid::Capabilities::SHADER_INT64_ATOMIC_ALL_OPS
    } else {
        naga::valid::Capabilities::empty()
    }
}

/// A scene's shader constants: axial damping, 32-point strands, two Newton iterations.
fn consts(bend: bool, colliders: u32) -> wethair::gpu::pipelines::SceneConsts {
    wethair::gpu::pipelines::SceneConsts {
        axial: true,
        colliders,
        bend,
        max_points: 32,
        iterations: 2,
        bdf2: false,
        roots: bend,
        // Each reaction form: word pairs without bend springs, 64-bit adds with them (the
        // gathered form is added to the wet modules in `all_modules`).
        atomic64: bend,
        gathered: false,
        bundle_points: 0,
    }
}

/// Every module a scene can compile: dry and wet hair for each GPU integrator (and wet hair
/// with liquid bridges), water, vertex output, shared water, held water and the bridges, for
/// a scene with and without bend springs and colliders.
fn all_modules() -> Vec<(String, String)> {
    use wethair::gpu::pipelines::{
        bridges_source, hair_source, held_source, output_source, water_output_source, water_source,
    };
    use wethair::plan::{pass_list, Pass};
    use wethair::{Integrator, Shape, SimParams};
    let mut out = Vec::new();
    for (bend, colliders) in [(false, 0u32), (true, 2)] {
        let c = consts(bend, colliders);
        let mut p = SimParams {
            air_drag: 0.1,
            ..SimParams::paper()
        };
        for _ in 0..colliders {
            p.colliders.push(Shape::Sphere {
                center: glam::Vec3::ZERO,
                radius: 0.1,
            });
        }
        for integrator in [
            Integrator::SYMPLECTIC_EULER,
            Integrator::IMPLICIT_EULER,
            Integrator::BDF2,
        ] {
            let c = wethair::gpu::pipelines::SceneConsts {
                bdf2: integrator == Integrator::BDF2,
                ..c
            };
            for wet in [false, true] {
                let passes: Vec<Pass> = pass_list(&p, integrator, bend, wet);
                let name = format!("hair {integrator:?} wet={wet} bend={bend} colliders={colliders}");
                out.push((name, hair_source(c, &passes)));
            }
            // A guide groom's paper model: each point pulls the particles back with its
            // bundle's hair, its reactions added or gathered.
            for gathered in [false, true] {
                let guides = wethair::gpu::pipelines::SceneConsts {
                    bundle_points: 1000,
                    gathered,
                    ..c
                };
                let name =
                    format!("hair {integrator:?} wet, guides, gathered={gathered} bend={bend} colliders={colliders}");
                out.push((name, hair_source(guides, &pass_list(&p, integrator, bend, true))));
            }
            let gathered = wethair::gpu::pipelines::SceneConsts { gathered: true, ..c };
            let name = format!("hair {integrator:?} wet, reactions gathered, bend={bend} colliders={colliders}");
            out.push((name, hair_source(gathered, &pass_list(&p, integrator, bend, true))));
            let bridged = SimParams {
                held_water: wethair::HeldWater::ON,
                ..p.clone()
            };
            let passes: Vec<Pass> = pass_list(&bridged, integrator, bend, true);
            assert!(passes.contains(&Pass::Cohesion));
            let name = format!("hair {integrator:?} bridges bend={bend} colliders={colliders}");
            out.push((name, hair_source(c, &passes)));
            // A guide groom's: absorption asks by each point's bundle.
            let guides = wethair::gpu::pipelines::SceneConsts {
                bundle_points: 1000,
                ..c
            };
            let name = format!("hair {integrator:?} bridges, guides, bend={bend} colliders={colliders}");
            out.push((name, hair_source(guides, &passes)));
        }
        out.push((format!("bridges bend={bend}"), bridges_source(c, 2048, 1000)));
        out.push((format!("water bend={bend}"), water_source(c)));
        out.push((
            format!("reactions bend={bend}"),
            wethair::gpu::pipelines::reactions_source(wethair::gpu::pipelines::SceneConsts { gathered: true, ..c }),
        ));
        out.push((
            format!("reactions bend={bend} bundles"),
            wethair::gpu::pipelines::reactions_source(wethair::gpu::pipelines::SceneConsts {
                gathered: true,
                bundle_points: 1000,
                ..c
            }),
        ));
        out.push((format!("piles bend={bend}"), wethair::gpu::pipelines::piles_source(c)));
        out.push((format!("output bend={bend}"), output_source(c)));
        out.push((format!("water output bend={bend}"), water_output_source(c)));
        out.push((
            format!("guide frames bend={bend}"),
            wethair::gpu::pipelines::guide_frames_source(c),
        ));
        out.push((
            format!("followers bend={bend}"),
            wethair::gpu::pipelines::write_followers_source(c),
        ));
        out.push((format!("held bend={bend}"), held_source(c, 1000)));
        // A guide groom's: bundles and quanta read after every point's limits and masses.
        let guides = wethair::gpu::pipelines::SceneConsts {
            bundle_points: 1000,
            ..c
        };
        out.push((format!("held bend={bend} bundles"), held_source(guides, 1000)));
        out.push((format!("roots bend={bend}"), wethair::gpu::pipelines::roots_source(c)));
        out.push((
            format!("volume spread bend={bend}"),
            wethair::gpu::pipelines::volume_spread_source(c),
        ));
        out.push((
            format!("volume respond bend={bend}"),
            wethair::gpu::pipelines::volume_respond_source(c),
        ));
    }
    out
}

/// The WGSL twins of the Rust GPU records, read back from every compiled module through naga's
/// reflection: the same member names in the same order, at the same byte offsets, and the
/// same size (a field added on one side only, or a vec3 that shifts what follows, fails here
/// before any device runs the shader). Also the per-substep uniform: the head matrix, then
/// colliders at the Rust stride.
#[test]
fn wgsl_struct_layouts_equal_the_rust_records() {
    use wethair::gpu::buffers::{ColliderGpu, SUBSTEP_HEAD_BYTES};
    use wethair::gpu::wgsl::records;
    let mut checked = 0;
    for (name, src) in all_modules() {
        let module =
            naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities(&src))
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let find = |ty: &str| {
            module
                .types
                .iter()
                .find(|(_, t)| t.name.as_deref() == Some(ty))
                .map(|(_, t)| t.inner.clone())
                .unwrap_or_else(|| panic!("{name}: no struct {ty}"))
        };
        for (ty, fields, size) in records() {
            let naga::TypeInner::Struct { members, span } = find(ty) else {
                panic!("{name}: {ty} is not a struct")
            };
            let wgsl: Vec<(String, u32)> = members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                .collect();
            let rust: Vec<(String, u32)> = fields.iter().map(|f| (f.name.to_string(), f.offset as u32)).collect();
            assert_eq!(wgsl, rust, "{name}: {ty}'s members and offsets");
            assert_eq!(span as usize, size, "{name}: size of {ty}");
            checked += 1;
        }
        let naga::TypeInner::Struct { members, .. } = find("Substep") else {
            panic!("{name}: Substep is not a struct")
        };
        assert_eq!(members[1].offset, 64, "{name}: the blend follows the head matrix");
        assert_eq!(
            members[2].offset, SUBSTEP_HEAD_BYTES,
            "{name}: colliders follow the head matrix and the blend"
        );
        let naga::TypeInner::Array { stride, .. } = module.types[members[2].ty].inner else {
            panic!("{name}: Substep.colliders is not an array")
        };
        assert_eq!(
            stride as usize,
            std::mem::size_of::<ColliderGpu>(),
            "{name}: collider stride"
        );
    }
    assert_eq!(
        checked,
        records().len() * 70,
        "every record in every module (70 modules)"
    );
}

/// The generated constants are the Rust values, as each module compiles them (naga evaluates
/// the declarations): a constant retyped in WGSL, or one the prelude stopped emitting, fails.
#[test]
fn wgsl_constants_equal_the_rust_values() {
    use wethair::gpu::wgsl::{constants, Const};
    for (name, src) in all_modules() {
        let module =
            naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
        for (cname, want) in constants() {
            let (_, c) = module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(cname))
                .unwrap_or_else(|| panic!("{name}: no constant {cname}"));
            let got = &module.global_expressions[c.init];
            match (want, got) {
                (Const::U32(v), naga::Expression::Literal(naga::Literal::U32(g))) => {
                    assert_eq!(*g, v, "{name}: {cname}")
                }
                (Const::F32(v), naga::Expression::Literal(naga::Literal::F32(g))) => {
                    assert_eq!(g.to_bits(), v.to_bits(), "{name}: {cname}")
                }
                _ => panic!("{name}: {cname} is {got:?}, expected {want:?}"),
            }
        }
    }
}
