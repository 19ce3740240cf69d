//! `<transform>` elements: `translate`, `scale`, `rotate`, `lookat`, `matrix`.
//!
//! Each operation left-multiplies the matrix built so far, so it applies *after* the
//! operations written above it (Mitsuba and Nori agree on this).

use glam::{DMat4, DVec3, DVec4, Mat4};

use super::xml::{parse_number, parse_numbers, Element};
use super::Error;

/// Reads the operations inside a `<transform>` element into one matrix.
pub fn parse(el: &Element) -> Result<Mat4, Error> {
    let mut m = DMat4::IDENTITY;
    for op in &el.children {
        let step = match op.tag.as_str() {
            "translate" => DMat4::from_translation(xyz(op, 0.0)?),
            "scale" => DMat4::from_scale(xyz(op, 1.0)?),
            "rotate" => rotate(op)?,
            "lookat" | "lookAt" => lookat_element(op)?,
            "matrix" => matrix(op)?,
            other => {
                return Err(op.err(format!(
                    "unexpected <{other}> in <transform> (expected translate, scale, rotate, lookat or matrix)"
                )))
            }
        };
        m = step * m;
    }
    if !m.is_finite() {
        return Err(el.err("the transform is not finite"));
    }
    Ok(m.as_mat4())
}

/// The camera-to-world frame of a camera at `origin` looking at `target`, the way
/// Mitsuba builds it: dir = normalize(target - origin), left = normalize(cross(up, dir)),
/// new_up = cross(dir, left); columns left, new_up, dir, origin. `None` when the frame
/// is degenerate (origin == target, or `up` parallel to the view direction).
pub fn look_at(origin: DVec3, target: DVec3, up: DVec3) -> Option<DMat4> {
    let dir = (target - origin).try_normalize()?;
    let left = up.cross(dir).try_normalize()?;
    let new_up = dir.cross(left);
    Some(DMat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        origin.extend(1.0),
    ))
}

/// A vector from `value` ("x,y,z", or one number for all three) or from `x`, `y`, `z`
/// attributes, each defaulting to `default`.
fn xyz(op: &Element, default: f64) -> Result<DVec3, Error> {
    op.check_attrs(&["value", "x", "y", "z"])?;
    if let Some(v) = op.attr("value") {
        if op.attr("x").is_some() || op.attr("y").is_some() || op.attr("z").is_some() {
            return Err(op.err(format!(
                "<{}> takes either 'value' or 'x'/'y'/'z', not both",
                op.tag
            )));
        }
        return vec3(op, "value", v, true);
    }
    let mut out = DVec3::splat(default);
    for (i, name) in ["x", "y", "z"].iter().enumerate() {
        if let Some(s) = op.attr(name) {
            out[i] = parse_number(s)
                .ok_or_else(|| op.err(format!("could not parse '{name}' = \"{s}\" as a number")))?;
        }
    }
    Ok(out)
}

/// Parses three numbers (or one, splatted, when `splat` is set) from attribute `name`.
fn vec3(op: &Element, name: &str, s: &str, splat: bool) -> Result<DVec3, Error> {
    let v = parse_numbers(s)
        .ok_or_else(|| op.err(format!("could not parse '{name}' = \"{s}\" as numbers")))?;
    match v.len() {
        3 => Ok(DVec3::new(v[0], v[1], v[2])),
        1 if splat => Ok(DVec3::splat(v[0])),
        n => Err(op.err(format!(
            "'{name}' of <{}> needs {} numbers, found {n}",
            op.tag,
            if splat { "1 or 3" } else { "3" }
        ))),
    }
}

/// `axis="x,y,z"` (Nori) or `x`/`y`/`z` or `value` (Mitsuba), and `angle` in degrees.
fn rotate(op: &Element) -> Result<DMat4, Error> {
    op.check_attrs(&["axis", "angle", "value", "x", "y", "z"])?;
    let axis = match op.attr("axis") {
        Some(s) => vec3(op, "axis", s, false)?,
        None => {
            let stripped = Element {
                attrs: op
                    .attrs
                    .iter()
                    .filter(|(k, _)| k != "angle")
                    .cloned()
                    .collect(),
                ..op.clone()
            };
            xyz(&stripped, 0.0)?
        }
    };
    let angle_s = op.require("angle")?;
    let angle = parse_number(angle_s)
        .ok_or_else(|| op.err(format!("could not parse angle \"{angle_s}\" as a number")))?;
    if axis == DVec3::ZERO {
        return Err(op.err("<rotate> needs a non-zero axis"));
    }
    Ok(rodrigues(axis, angle.to_radians()))
}

/// Rodrigues' rotation matrix `cos θ I + (1 − cos θ) a aᵀ + sin θ [a]×` with the axis
/// `a` as written, not normalized, as Mitsuba 3 (Dr.Jit's `rotate`) and Nori (Eigen's
/// `AngleAxis`) build it: a unit axis gives a rotation, any other one also scales and
/// shears, in both renderers alike. (Mitsuba 3.9 then turns normals by this same
/// matrix instead of its inverse transpose; wavetrace keeps normals perpendicular to
/// the transformed surface.)
fn rodrigues(a: DVec3, theta: f64) -> DMat4 {
    let (s, c) = theta.sin_cos();
    let cm = 1.0 - c;
    DMat4::from_cols(
        DVec4::new(
            a.x * a.x * cm + c,
            a.y * a.x * cm + a.z * s,
            a.z * a.x * cm - a.y * s,
            0.0,
        ),
        DVec4::new(
            a.x * a.y * cm - a.z * s,
            a.y * a.y * cm + c,
            a.z * a.y * cm + a.x * s,
            0.0,
        ),
        DVec4::new(
            a.x * a.z * cm + a.y * s,
            a.y * a.z * cm - a.x * s,
            a.z * a.z * cm + c,
            0.0,
        ),
        DVec4::W,
    )
}

fn lookat_element(op: &Element) -> Result<DMat4, Error> {
    op.check_attrs(&["origin", "target", "up"])?;
    let origin = vec3(op, "origin", op.require("origin")?, false)?;
    let target = vec3(op, "target", op.require("target")?, false)?;
    let dir = target - origin;
    let up = match op.attr("up") {
        Some(s) => vec3(op, "up", s, false)?,
        // Mitsuba picks any up vector perpendicular to the view direction.
        None => dir.normalize_or_zero().any_orthonormal_vector(),
    };
    look_at(origin, target, up).ok_or_else(|| {
        op.err("invalid <lookat>: origin equals target, or 'up' is parallel to the view direction")
    })
}

/// 16 numbers, row-major (or 9 for the upper 3x3, as Mitsuba allows).
fn matrix(op: &Element) -> Result<DMat4, Error> {
    op.check_attrs(&["value"])?;
    let s = op.require("value")?;
    let v = parse_numbers(s)
        .ok_or_else(|| op.err(format!("could not parse <matrix> value \"{s}\" as numbers")))?;
    match v.len() {
        16 => Ok(DMat4::from_cols_slice(&v).transpose()),
        9 => Ok(DMat4::from_cols(
            DVec4::new(v[0], v[3], v[6], 0.0),
            DVec4::new(v[1], v[4], v[7], 0.0),
            DVec4::new(v[2], v[5], v[8], 0.0),
            DVec4::W,
        )),
        n => Err(op.err(format!("<matrix> needs 16 numbers (row-major), found {n}"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotate_is_rodrigues_with_the_axis_as_written() {
        // Mitsuba 3.9.1: mi.ScalarTransform4f().rotate([1, 2, 0.5], 37).matrix, rows.
        let mitsuba = [
            [1.0, 0.101822, 1.30431],
            [0.703637, 1.60409, -0.40045],
            [-1.10295, 0.80318, 0.848977],
        ];
        let m = rodrigues(DVec3::new(1.0, 2.0, 0.5), 37f64.to_radians());
        for (r, row) in mitsuba.iter().enumerate() {
            for (c, want) in row.iter().enumerate() {
                assert!(
                    (m.col(c)[r] - want).abs() < 1e-5,
                    "({r}, {c}): {}",
                    m.col(c)[r]
                );
            }
        }
        // A unit axis: glam's rotation.
        let a = DVec3::new(0.3, -0.4, 0.5).normalize();
        let r = DMat4::from_axis_angle(a, 1.1);
        assert!(rodrigues(a, 1.1).abs_diff_eq(r, 1e-12));
    }
}
