//! Warnings a command reports: each printed to standard error once, as it
//! arises, and listed under `"warnings"` in the command's `--json` output
//! (an object each: `"kind"`, `"message"`, and for a glass used outside
//! its data `"glass"`, `"range_nm"` and `"wavelength_nm"`).

use serde_json::{json, Value};
use std::sync::Mutex;

/// This process's warnings, in the order they arose.
static WARNINGS: Mutex<Vec<Value>> = Mutex::new(Vec::new());

/// Reports a warning of `kind` (a short identifier) saying `message`.
pub fn warn(kind: &str, message: impl std::fmt::Display) {
    push(json!({"kind": kind, "message": message.to_string()}));
}

/// Reports a glass used outside its data.
pub fn glass_range(w: &lens::glass::RangeWarning) {
    push(json!({
        "kind": "glass_range",
        "message": w.to_string(),
        "glass": w.glass,
        "range_nm": w.range_nm,
        "wavelength_nm": w.wavelength_nm,
    }));
}

fn push(v: Value) {
    let mut all = WARNINGS.lock().unwrap_or_else(|e| e.into_inner());
    if all.contains(&v) {
        return;
    }
    eprintln!("warning: {}", v["message"].as_str().unwrap_or_default());
    all.push(v);
}

/// The warnings so far.
pub fn all() -> Vec<Value> {
    WARNINGS.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

/// `v` with the warnings so far under `"warnings"`, where `v` is an object
/// and there are any.
pub fn attach(mut v: Value) -> Value {
    let all = all();
    if let (Value::Object(map), false) = (&mut v, all.is_empty()) {
        map.insert("warnings".into(), Value::Array(all));
    }
    v
}
