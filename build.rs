//! Sets the shared library's SONAME on Linux as cargo-c does: `libwethair.so.MAJOR`, or
//! `libwethair.so.0.MINOR` before 1.0 (where a minor release may break the ABI), so installed
//! programs load a compatible library and side-by-side installs work.
fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        let major = env!("CARGO_PKG_VERSION_MAJOR");
        let soname = if major == "0" {
            format!("libwethair.so.0.{}", env!("CARGO_PKG_VERSION_MINOR"))
        } else {
            format!("libwethair.so.{major}")
        };
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,{soname}");
    }
}
