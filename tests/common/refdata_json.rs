//! Reading the reference data (tests/data/refdata/*.json): numbers are JSON
//! strings with 17 significant digits. Shared by the refdata and trajectory
//! tests.
#![allow(dead_code)] // each test binary uses a part

use nonholonomic::prelude::SVector;
use serde_json::Value;

/// The JSON of a reference system.
pub fn load(name: &str) -> Value {
    let path = format!(
        "{}/tests/data/refdata/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// A JSON number string as `f64`.
pub fn num(v: &Value) -> f64 {
    let s = v
        .as_str()
        .unwrap_or_else(|| panic!("expected a number string, got {v}"));
    s.parse::<f64>()
        .unwrap_or_else(|e| panic!("cannot parse {s:?}: {e}"))
}

/// A JSON array.
pub fn arr(v: &Value) -> &Vec<Value> {
    v.as_array()
        .unwrap_or_else(|| panic!("expected an array, got {v}"))
}

/// A JSON array of number strings as a vector of length `M`.
pub fn vector<const M: usize>(v: &Value) -> SVector<f64, M> {
    let a = arr(v);
    assert_eq!(a.len(), M, "length of {v}");
    SVector::<f64, M>::from_fn(|i, _| num(&a[i]))
}
