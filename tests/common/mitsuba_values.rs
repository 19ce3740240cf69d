//! Readers of the JSON that tools/mitsuba_*_values.py write (BSDF values Mitsuba 3
//! computed), shared by the tests that compare the GPU's eval and pdf with them.

use glam::Vec3;
use serde_json::Value;

/// Half an f32 ulp at 1 (the unit roundoff, 2⁻²⁴).
pub const EPS: f64 = f32::EPSILON as f64 / 2.0;

/// A JSON array of three numbers.
pub fn v3(v: &Value) -> Vec3 {
    let a: Vec<f32> = v
        .as_array()
        .expect("a vector")
        .iter()
        .map(|x| x.as_f64().expect("a number") as f32)
        .collect();
    Vec3::new(a[0], a[1], a[2])
}

/// A JSON number.
pub fn num(v: &Value) -> f32 {
    v.as_f64().expect("a number") as f32
}
