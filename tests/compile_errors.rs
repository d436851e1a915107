//! The compile-fail suite (`tests/ui/<family>/*.rs` with their `.stderr`)
//! and valid edge cases that must compile and run (`tests/pass/*.rs`).
//! Regenerate the snapshots after an intended change of a message with
//! `TRYBUILD=overwrite cargo test --test compile_errors`.

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*/*.rs");
    t.pass("tests/pass/*.rs");
}
