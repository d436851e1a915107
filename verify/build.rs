//! Writes the dense synthetic system of 20 coordinates (the smallest of its
//! family whose accelerations the engine splits into chunks, see
//! `nh-macros/core/tests/synthetic`) as a `system!` invocation that the
//! interpreter's tests include, so that it is both compiled and interpreted.
#[path = "../nh-macros/core/tests/synthetic/mod.rs"]
mod synthetic;

fn main() {
    let out = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR");
    let text = synthetic::dense(20, "");
    let code = format!("system!(DENSE20, {{ {text} }});\n");
    std::fs::write(format!("{out}/dense20.rs"), code).expect("OUT_DIR is writable");
    println!("cargo::rerun-if-changed=../nh-macros/core/tests/synthetic/mod.rs");
    println!("cargo::rerun-if-changed=build.rs");
}
