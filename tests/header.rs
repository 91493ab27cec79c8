//! The committed `include/wethair.h` must equal a fresh cbindgen generation (with version
//! macros from Cargo.toml). `WETHAIR_BLESS=1` rewrites it instead of failing.

use std::path::Path;

fn generate() -> String {
    let dir = env!("CARGO_MANIFEST_DIR");
    let mut config = cbindgen::Config::from_file(Path::new(dir).join("cbindgen.toml")).expect("cbindgen.toml");
    let (ma, mi, pa) = (
        env!("CARGO_PKG_VERSION_MAJOR"),
        env!("CARGO_PKG_VERSION_MINOR"),
        env!("CARGO_PKG_VERSION_PATCH"),
    );
    let compat = config.after_includes.take().unwrap_or_default();
    config.after_includes = Some(format!(
        "{compat}\n\n/* Version of this header; compare WETHAIR_VERSION with wethair_version() at run time. */\n\
         #define WETHAIR_VERSION_MAJOR {ma}\n#define WETHAIR_VERSION_MINOR {mi}\n#define WETHAIR_VERSION_PATCH {pa}\n\
         #define WETHAIR_VERSION (WETHAIR_VERSION_MAJOR * 10000 + WETHAIR_VERSION_MINOR * 100 + WETHAIR_VERSION_PATCH)\n\
         #define WETHAIR_VERSION_STRING \"{ma}.{mi}.{pa}\"\n"
    ));
    let mut out = Vec::new();
    cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header")
        .write(&mut out);
    String::from_utf8(out).expect("utf-8 header")
}

#[test]
fn committed_header_equals_fresh_generation() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/wethair.h");
    let fresh = generate();
    if std::env::var_os("WETHAIR_BLESS").is_some() {
        std::fs::write(&path, &fresh).expect("write header");
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == fresh,
        "include/wethair.h is stale: run `WETHAIR_BLESS=1 cargo test --release --test all header::` and commit it"
    );
}

#[test]
fn header_version_matches_library() {
    let h = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("include/wethair.h")).unwrap();
    let major: u32 = env!("CARGO_PKG_VERSION_MAJOR").parse().unwrap();
    assert!(h.contains(&format!("#define WETHAIR_VERSION_MAJOR {major}")));
    let v = wethair::ffi::wethair_version();
    let (ma, mi, pa): (u32, u32, u32) = (
        env!("CARGO_PKG_VERSION_MAJOR").parse().unwrap(),
        env!("CARGO_PKG_VERSION_MINOR").parse().unwrap(),
        env!("CARGO_PKG_VERSION_PATCH").parse().unwrap(),
    );
    assert_eq!(v, ma * 10000 + mi * 100 + pa);
}

/// Every enum constant the library validates and names (`c_enum!`) is in the header with its
/// value, and the header declares no other `WETHAIR_*` enum constant besides the kept
/// `*_FORCE32` names: the C names come from one definition per enum.
#[test]
fn header_enum_constants_equal_the_validated_ones() {
    let h = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("include/wethair.h")).unwrap();
    let consts = wethair::ffi::c_enum_constants();
    for (ty, name, value) in &consts {
        assert!(
            h.contains(&format!("  {name} = {value},")),
            "{ty}::{name} = {value} is not in the header"
        );
        // wethair_result_string names results as the header does.
        if *ty == "WetHairResult" {
            let s = unsafe { std::ffi::CStr::from_ptr(wethair::ffi::wethair_result_string(*value)) };
            assert_eq!(s.to_str().unwrap(), *name);
        }
    }
    let declared: Vec<&str> = h
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("WETHAIR_") && l.contains(" = ") && !l.contains("FORCE32"))
        .map(|l| l.split(' ').next().unwrap())
        .collect();
    assert_eq!(declared.len(), consts.len(), "header constants: {declared:?}");
}
