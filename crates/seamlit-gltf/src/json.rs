//! Reading and writing glTF JSON as [`serde_json::Value`]: indices and counts (also written
//! as floats, which glTF allows), array members, and the numbers of the specification that
//! the reader, the decoders and the writers share (buffer view targets, component types,
//! components per accessor type).

use serde_json::Value;

/// The array member `key` of the document `json` (a JSON object), made an empty array when
/// missing or not an array.
pub(crate) fn array_member<'j>(json: &'j mut Value, key: &str) -> &'j mut Vec<Value> {
    if !json[key].is_array() {
        json[key] = Value::Array(Vec::new());
    }
    json[key].as_array_mut().expect("made an array above")
}

/// An index (a non-negative integer, also written as a float).
pub(crate) fn index(value: &Value) -> Option<usize> {
    integer(value).and_then(|n| usize::try_from(n).ok())
}

/// A non-negative integer member of a JSON object.
pub(crate) fn usize_member(value: &Value, key: &str) -> Option<usize> {
    value.get(key).and_then(integer).and_then(|n| usize::try_from(n).ok())
}

/// A non-negative integer, also when written as a float (`3.0`, which glTF allows).
#[expect(clippy::cast_possible_truncation, reason = "a whole number in u64's range, checked")]
pub(crate) fn integer(value: &Value) -> Option<u64> {
    value.as_u64().or_else(|| {
        let x = value.as_f64()?;
        // x is a whole number in u64's range, checked first.
        (x.fract() == 0.0 && (0.0..1.8e19).contains(&x)).then_some(x as u64)
    })
}

/// A primitive's `mode` for a list of triangles.
pub(crate) const TRIANGLES: u64 = 4;

/// `ARRAY_BUFFER` and `ELEMENT_ARRAY_BUFFER`, buffer view targets.
pub(crate) const ARRAY_BUFFER: u32 = 34962;
pub(crate) const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// Accessor component types (`componentType`, glTF 2.0, "Accessor data types").
pub(crate) const BYTE: u64 = 5120;
/// `UNSIGNED_BYTE`.
pub(crate) const UNSIGNED_BYTE: u64 = 5121;
/// `SHORT`.
pub(crate) const SHORT: u64 = 5122;
/// `UNSIGNED_SHORT`.
pub(crate) const UNSIGNED_SHORT: u64 = 5123;
/// `UNSIGNED_INT`.
pub(crate) const UNSIGNED_INT: u64 = 5125;
/// `FLOAT`.
pub(crate) const FLOAT: u64 = 5126;

/// An accessor `type` as (columns, rows): `SCALAR` (1, 1), `VEC2` to `VEC4` (1, n), `MAT2`
/// to `MAT4` (n, n); its components are columns x rows. `None` for any other type.
pub(crate) fn shape(accessor_type: &str) -> Option<(usize, usize)> {
    match accessor_type {
        "SCALAR" => Some((1, 1)),
        "VEC2" => Some((1, 2)),
        "VEC3" => Some((1, 3)),
        "VEC4" => Some((1, 4)),
        "MAT2" => Some((2, 2)),
        "MAT3" => Some((3, 3)),
        "MAT4" => Some((4, 4)),
        _ => None,
    }
}
