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
    use wethair::gpu::pipelines::{output_source, water_output_source, water_source, SceneConsts};
    for (bend, colliders) in [(false, 0), (true, 2)] {
        let c = SceneConsts {
            axial: true,
            colliders,
            bend,
            max_points: 32,
            iterations: 2,
        };
        for (name, src, entry) in [
            ("output", output_source(c), "write_vertices"),
            ("water", water_source(c), "water_cull"),
            ("water output", water_output_source(c), "write_water_vertices"),
        ] {
            let module =
                naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
            naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
                .validate(&module)
                .unwrap_or_else(|e| panic!("{name}: {e:?}"));
            assert!(
                module.entry_points.iter().any(|e| e.name == entry),
                "{name} has no {entry}"
            );
        }
    }
}
