//! `ellipsoids`: a cloud of anisotropic ellipsoids, as Mitsuba 3.9 makes them
//! (src/shapes/ellipsoids.cpp, ellipsoids.h): each a centre, three scales and a
//! rotation, intersected in closed form. Rays are met from outside only: a ray that
//! starts inside an ellipsoid (or whose nearer crossing is behind it) does not hit it
//! (Mitsuba culls the back faces).
//!
//! The file is a PLY file whose first element holds one ellipsoid an entry, its
//! properties `x y z nx ny nz` first and `scale_0 scale_1 scale_2 rot_0 rot_1 rot_2
//! rot_3` last (others between are Mitsuba's attributes, ignored here). As Mitsuba
//! 3.9.1 reads it: the scales are logarithms (the ellipsoid's semi-axes are their
//! exponentials, at least 1e-6, times `scale_factor`, times the mean scale of
//! `to_world`, times `extent`); `rot_0` is the quaternion's real part; `to_world`
//! moves the centres and rotates the quaternions by its rotation.
//!
//! At a hit, as Mitsuba reports it: the normal is the ellipsoid's own, geometric and
//! shading alike; uv = (0, 0); the tangent frame is built from the normal (Mitsuba
//! leaves ∂p/∂u zero).
//!
//! On the GPU an ellipsoid's primitive holds its box and the offset of its 12 numbers
//! in the grid buffer (after the sdfgrids and B-spline curves: [`place`], [`pack`]):
//! its centre and the rows of the map M = diag(1 / semi-axes) Rᵀ that takes it to the
//! unit sphere.
//!
//! ```xml
//! <shape type="ellipsoids"><string name="filename" value="primitives.ply"/></shape>
//! ```

use std::path::Path;

use glam::{Mat3, Quat, Vec3};

use super::{Geometry, Mesh, TO_WORLD};
use crate::scene::builder;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "ellipsoids",
    "A cloud of anisotropic ellipsoids (centre, log-scales, rotation quaternion) from a PLY file, intersected in closed form, back faces culled; uv = 0. Only the `filename` form (Mitsuba's `data`/`centers` tensors cannot be written in XML); no area emitters or media on them yet; attributes other than the geometry are ignored.",
    &[
        Param::new(
            "filename",
            "string",
            "",
            "the PLY file: `x y z nx ny nz` first, `scale_0..2 rot_0..3` last (required)",
        ),
        Param::new(
            "extent",
            "float",
            "3",
            "the semi-axes are the file's scales times this",
        ),
        Param::new(
            "scale_factor",
            "float",
            "1",
            "a factor on every ellipsoid's scales",
        ),
        Param::new(
            "to_world",
            TO_WORLD.ty,
            TO_WORLD.default,
            "moves the centres, rotates the ellipsoids and scales them by its mean scale",
        ),
    ],
);

/// The marker of an ellipsoid entry in [`Mesh::indices`]: `[its number, this, its
/// grid-buffer offset]`.
pub const MARKER: u32 = 10;
/// Numbers per ellipsoid in the grid buffer.
pub const WORDS: usize = 12;

/// One ellipsoid in world space: its centre, semi-axes (extent applied) and rotation
/// (object to world).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipsoid {
    pub center: Vec3,
    pub scale: Vec3,
    pub rotation: Quat,
}

impl Ellipsoid {
    /// M = diag(1 / scale) Rᵀ: world offsets from the centre to the unit sphere.
    pub fn to_unit(&self) -> Mat3 {
        let rt = Mat3::from_quat(self.rotation).transpose();
        Mat3::from_diagonal(self.scale.recip()) * rt
    }

    /// The box holding it (the extent of the rotated axes along x, y, z).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let r = Mat3::from_quat(self.rotation);
        let a = [
            r.x_axis * self.scale.x,
            r.y_axis * self.scale.y,
            r.z_axis * self.scale.z,
        ];
        let e = Vec3::new(
            Vec3::new(a[0].x, a[1].x, a[2].x).length(),
            Vec3::new(a[0].y, a[1].y, a[2].y).length(),
            Vec3::new(a[0].z, a[1].z, a[2].z).length(),
        );
        (self.center - e, self.center + e)
    }

    /// The entry distance of ray (o, d) in [tmin, tmax], as Mitsuba decides it: none
    /// when the nearer crossing is behind the origin (a ray starting inside misses).
    pub fn intersect(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<f32> {
        let m = self.to_unit();
        let o = m * (o - self.center);
        let d = m * d;
        let a = d.length_squared();
        let b = -o.dot(d);
        let c = o.length_squared() - 1.0;
        let discr = 1.0 - (o + (b / a) * d).length_squared();
        if discr.is_nan() || discr < 0.0 || a.is_nan() || a <= 0.0 {
            return None;
        }
        let q = b + (a * discr).sqrt().copysign(b);
        let (t0, t1) = (c / q, q / a);
        let near = t0.min(t1);
        (near >= tmin && near <= tmax).then_some(near)
    }

    /// The unit normal at point `p` of its surface.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        let m = self.to_unit();
        (m.transpose() * (m * (p - self.center))).normalize()
    }
}

/// A Mitsuba `ellipsoids`: the ellipsoids in world space (`to_world` applied, as
/// Mitsuba applies it when it reads the file).
pub fn mitsuba(el: &Element, props: &Properties) -> Result<Geometry, Error> {
    for key in ["data", "centers"] {
        if props.has(key) {
            return Err(props.error(
                key,
                format!("ellipsoids' '{key}' is a tensor, which a scene file cannot hold: use 'filename'"),
            ));
        }
    }
    let path = builder::mesh_path(el, props, "filename")?;
    let extent = props.float("extent", 3.0)?;
    if !(extent.is_finite() && extent > 0.0) {
        return Err(props.error(
            "extent",
            format!("'extent' must be positive and finite, not {extent}"),
        ));
    }
    let scale_factor = props.float("scale_factor", 1.0)?;
    if !(scale_factor.is_finite() && scale_factor > 0.0) {
        return Err(props.error(
            "scale_factor",
            format!("'scale_factor' must be positive and finite, not {scale_factor}"),
        ));
    }
    let to_world = props.transform("to_world")?;
    let (r, world_scale) = polar(Mat3::from_mat4(to_world));
    if !(to_world.is_finite() && world_scale != 0.0 && r.is_finite()) {
        return Err(props.error("to_world", "'to_world' must be an invertible affine map"));
    }
    let bytes = std::fs::read(&path).map_err(|e| Error::file(&path, format!("{e}")))?;
    let raw = parse(&path, &bytes)?;
    let mut mesh = Mesh {
        name: path.display().to_string(),
        ..Mesh::default()
    };
    for (k, e) in raw.iter().enumerate() {
        let center = to_world.transform_point3(e.center);
        let scale = e.scale.exp().max(Vec3::splat(1e-6)) * scale_factor * world_scale * extent;
        let rotation = (r * e.rotation).normalize();
        let ell = Ellipsoid {
            center,
            scale,
            rotation,
        };
        if !(center.is_finite() && scale.is_finite() && rotation.is_finite()) {
            return Err(Error::file(
                &path,
                format!(
                    "ellipsoid {k}: its centre, scales or rotation are not finite in world space"
                ),
            ));
        }
        mesh.positions.push(center);
        mesh.radii.push(scale.abs().max_element());
        mesh.indices.push([k as u32, MARKER, 0]);
        mesh.ellipsoids.push(ell);
    }
    Ok(Geometry::Curves {
        mesh,
        to_world: glam::Mat4::IDENTITY,
    })
}

/// The rotation of `m`'s polar decomposition m = Q P (a reflection folded into P, as
/// Mitsuba's transform_decompose does) and the mean of P's diagonal: how Mitsuba
/// rotates and scales ellipsoids by `to_world`.
pub fn polar(m: Mat3) -> (Quat, f32) {
    let mut q = m;
    for _ in 0..25 {
        let inv_t = q.inverse().transpose();
        if !inv_t.is_finite() {
            return (Quat::NAN, 0.0);
        }
        q = (q + inv_t) * 0.5;
    }
    let mut p = q.transpose() * m;
    if q.determinant() < 0.0 {
        q = -q;
        p = -p;
    }
    let mean = (p.x_axis.x + p.y_axis.y + p.z_axis.z) / 3.0;
    (Quat::from_mat3(&q).normalize(), mean)
}

/// The ellipsoids of a PLY file as written (centre, log-scales, the quaternion with
/// `rot_0` its real part), before `to_world`, exp and `extent`.
pub fn parse(path: &Path, bytes: &[u8]) -> Result<Vec<Ellipsoid>, Error> {
    let err = |m: String| Error::file(path, m);
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .or_else(|| {
            bytes
                .windows(12)
                .position(|w| w == b"end_header\r\n")
                .map(|p| p + 1)
        })
        .ok_or_else(|| err("not a PLY file: no 'end_header' line".into()))?;
    let header =
        std::str::from_utf8(&bytes[..end]).map_err(|_| err("a PLY header must be text".into()))?;
    let body = &bytes[end + 11..];
    let mut lines = header.lines().map(str::trim_end);
    if lines.next() != Some("ply") {
        return Err(err("not a PLY file: it does not start with 'ply'".into()));
    }
    let mut format = None;
    let mut count: Option<usize> = None;
    let mut props: Vec<(String, &str)> = Vec::new();
    let mut in_first = false;
    for line in lines {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            ["format", f, _] => format = Some(f.to_string()),
            ["element", _, n] => {
                if count.is_some() {
                    in_first = false;
                    continue;
                }
                count = Some(
                    n.parse()
                        .map_err(|_| err(format!("bad element count '{n}'")))?,
                );
                in_first = true;
            }
            ["property", "list", ..] if in_first => {
                return Err(err(
                    "the ellipsoids' element cannot hold list properties".into()
                ))
            }
            ["property", ty, name] if in_first => props.push((name.to_string(), ty)),
            _ => {}
        }
    }
    let count = count.ok_or_else(|| err("the PLY file has no element".into()))?;
    let names: Vec<&str> = props.iter().map(|p| p.0.as_str()).collect();
    let n = names.len();
    let first = ["x", "y", "z", "nx", "ny", "nz"];
    let last = [
        "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3",
    ];
    if n < 13 || names[..6] != first || names[n - 7..] != last {
        return Err(err(format!(
            "ellipsoids need the properties 'x y z nx ny nz' first and 'scale_0 scale_1 scale_2 rot_0 rot_1 rot_2 rot_3' last (Mitsuba's layout); this file has '{}'",
            names.join(" ")
        )));
    }
    let sizes = type_sizes(path, &props)?;
    let mut values = vec![0f64; n];
    let mut out = Vec::with_capacity(count.min(1 << 24));
    let big = match format.as_deref() {
        Some("ascii") => None,
        Some("binary_little_endian") => Some(false),
        Some("binary_big_endian") => Some(true),
        f => return Err(err(format!("unknown PLY format {f:?}"))),
    };
    let stride: usize = sizes.iter().sum();
    // ASCII: each word with its line in the file (the body starts after end_header).
    let first_line = header.lines().count() as u32 + 2;
    let mut words = if big.is_none() {
        Some(
            std::str::from_utf8(body)
                .map_err(|_| err("an ASCII PLY file must be text".into()))?
                .lines()
                .enumerate()
                .flat_map(|(i, l)| l.split_whitespace().map(move |w| (i as u32, w))),
        )
    } else {
        None
    };
    let mut line = 0u32;
    // An error in entry k: at its line in ASCII files.
    let at = |line: u32, m: String| {
        if big.is_none() {
            Error::at(path, first_line + line, m)
        } else {
            Error::file(path, m)
        }
    };
    for k in 0..count {
        match (big, words.as_mut()) {
            (Some(big), _) => {
                let rec = body
                    .get(k * stride..(k + 1) * stride)
                    .ok_or_else(|| err(format!("the file ends inside ellipsoid {k} of {count}")))?;
                let mut at = 0;
                for (j, ((_, ty), size)) in props.iter().zip(&sizes).enumerate() {
                    values[j] = read_scalar(ty, &rec[at..at + size], big);
                    at += size;
                }
            }
            (None, Some(words)) => {
                for (j, v) in values.iter_mut().enumerate() {
                    let (l, w) = words.next().ok_or_else(|| {
                        err(format!("the file ends inside ellipsoid {k} of {count}"))
                    })?;
                    line = l;
                    *v = w.parse().map_err(|_| {
                        at(
                            line,
                            format!("ellipsoid {k}: '{}' is not a number ('{w}')", names[j]),
                        )
                    })?;
                }
            }
            _ => unreachable!("ASCII files have their words"),
        }
        let geometry = (0..3).chain(n - 7..n);
        if let Some(j) = geometry.clone().find(|&j| !values[j].is_finite()) {
            return Err(at(
                line,
                format!(
                    "ellipsoid {k}: '{}' is not finite ({})",
                    names[j], values[j]
                ),
            ));
        }
        let v = |j: usize| values[j] as f32;
        let rotation = Quat::from_xyzw(v(n - 3), v(n - 2), v(n - 1), v(n - 4));
        if rotation.length_squared() == 0.0 {
            return Err(at(
                line,
                format!("ellipsoid {k}: its quaternion 'rot_0..3' is zero"),
            ));
        }
        out.push(Ellipsoid {
            center: Vec3::new(v(0), v(1), v(2)),
            scale: Vec3::new(v(n - 7), v(n - 6), v(n - 5)),
            rotation,
        });
    }
    if out.is_empty() {
        return Err(err("the file holds no ellipsoids".into()));
    }
    Ok(out)
}

/// The size in bytes of each PLY property `(name, type)`.
fn type_sizes(path: &Path, props: &[(String, &str)]) -> Result<Vec<usize>, Error> {
    props
        .iter()
        .map(|(_, ty)| match *ty {
            "char" | "int8" | "uchar" | "uint8" => Ok(1),
            "short" | "int16" | "ushort" | "uint16" => Ok(2),
            "int" | "int32" | "uint" | "uint32" | "float" | "float32" => Ok(4),
            "double" | "float64" => Ok(8),
            t => Err(Error::file(
                path,
                format!("unknown PLY property type '{t}'"),
            )),
        })
        .collect()
}

fn read_scalar(ty: &str, b: &[u8], big: bool) -> f64 {
    macro_rules! get {
        ($t:ty) => {{
            let a = b.try_into().expect("sized by the type");
            (if big {
                <$t>::from_be_bytes(a)
            } else {
                <$t>::from_le_bytes(a)
            }) as f64
        }};
    }
    match ty {
        "char" | "int8" => get!(i8),
        "uchar" | "uint8" => get!(u8),
        "short" | "int16" => get!(i16),
        "ushort" | "uint16" => get!(u16),
        "int" | "int32" => get!(i32),
        "uint" | "uint32" => get!(u32),
        "float" | "float32" => get!(f32),
        _ => get!(f64),
    }
}

/// Gives each ellipsoid of `meshes` its place in the grid buffer, from word `base` on
/// (after the sdfgrids and B-spline curves); returns the end. Errs where the buffer
/// would grow past 2^31 words.
pub fn place(meshes: &mut [Mesh], base: usize) -> Result<usize, String> {
    let mut at = base as u64;
    for m in meshes.iter_mut().filter(|m| m.is_ellipsoids()) {
        let end = at + (WORDS * m.ellipsoids.len()) as u64;
        if end >= 1 << 31 {
            return Err(format!(
                "the scene's ellipsoids are too many: '{}' ends past 2^31 words of the grid buffer",
                m.name
            ));
        }
        for s in &mut m.indices {
            s[2] = (at + (WORDS as u64) * s[0] as u64) as u32;
        }
        at = end;
    }
    Ok(at as usize)
}

/// Appends the ellipsoids of `meshes` to the grid buffer `words` where [`place`] put
/// them: centre, then M's rows ([`Ellipsoid::to_unit`]).
pub fn pack(meshes: &[Mesh], words: &mut Vec<f32>) {
    for m in meshes.iter().filter(|m| m.is_ellipsoids()) {
        assert_eq!(
            words.len() as u64,
            m.indices[0][2] as u64,
            "ellipsoids follow the sdfgrids and curves in the grid buffer"
        );
        for e in &m.ellipsoids {
            let t = e.to_unit().transpose();
            words.extend_from_slice(&e.center.to_array());
            for c in [t.x_axis, t.y_axis, t.z_axis] {
                words.extend_from_slice(&c.to_array());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Vec<Ellipsoid>, Error> {
        parse(Path::new("e.ply"), text.as_bytes())
    }

    const HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float opacity\nproperty float scale_0\nproperty float scale_1\nproperty float scale_2\nproperty float rot_0\nproperty float rot_1\nproperty float rot_2\nproperty float rot_3\nend_header\n";

    #[test]
    fn ascii_and_binary() {
        let text = format!(
            "{HEADER}1 2 3 0 0 1 0.5 0 0.5 -1 1 0 0 0\n0 0 0 0 0 0 1 0 0 0 0.5 0.5 0.5 0.5\n"
        );
        let e = read(&text).unwrap();
        assert_eq!(e.len(), 2);
        assert_eq!(e[0].center, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(e[0].scale, Vec3::new(0.0, 0.5, -1.0));
        assert_eq!(e[0].rotation, Quat::IDENTITY);
        assert_eq!(e[1].rotation, Quat::from_xyzw(0.5, 0.5, 0.5, 0.5));
        let mut bin = HEADER.replace("ascii", "binary_little_endian").into_bytes();
        for v in [1f32, 2., 3., 0., 0., 1., 0.5, 0., 0.5, -1., 1., 0., 0., 0.] {
            bin.extend_from_slice(&v.to_le_bytes());
        }
        for v in [0f32, 0., 0., 0., 0., 0., 1., 0., 0., 0., 0.5, 0.5, 0.5, 0.5] {
            bin.extend_from_slice(&v.to_le_bytes());
        }
        assert_eq!(parse(Path::new("e.ply"), &bin).unwrap(), e);
    }

    #[test]
    fn errors_name_the_cause() {
        let msg = |t: &str| read(t).unwrap_err().to_string();
        assert!(msg(&format!(
            "{HEADER}1 2 3 0 0 1 0.5 0 0.5 nan 1 0 0 0\n0 0 0 0 0 0 1 0 0 0 1 0 0 0\n"
        ))
        .contains("ellipsoid 0: 'scale_2' is not finite"));
        assert!(msg(&format!("{HEADER}1 2 3 0 0 1 0.5 0 0.5 0 1 0 0 0\n"))
            .contains("ends inside ellipsoid 1"));
        assert!(msg(&HEADER.replace("scale_0", "s0")).contains("'x y z nx ny nz' first"));
        assert!(msg(&format!(
            "{HEADER}1 2 3 0 0 1 0.5 0 0.5 0 0 0 0 0\n0 0 0 0 0 0 1 0 0 0 1 0 0 0\n"
        ))
        .contains("quaternion"));
        assert!(msg("hello\n").contains("end_header"));
    }

    #[test]
    fn hits_from_outside_only() {
        let e = Ellipsoid {
            center: Vec3::new(0.0, 0.0, 5.0),
            scale: Vec3::new(1.0, 2.0, 0.5),
            rotation: Quat::from_rotation_y(0.3),
        };
        let t = e
            .intersect(Vec3::ZERO, Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        let p = t * Vec3::Z;
        let m = e.to_unit();
        assert!(((m * (p - e.center)).length() - 1.0).abs() < 1e-5);
        assert!(e.normal(p).z < 0.0);
        // From inside: none; from behind: none.
        assert!(e.intersect(e.center, Vec3::Z, 0.0, f32::INFINITY).is_none());
        assert!(e
            .intersect(Vec3::new(0.0, 0.0, 10.0), Vec3::Z, 0.0, f32::INFINITY)
            .is_none());
        let (lo, hi) = e.bounds();
        assert!(p.cmpge(lo).all() && p.cmple(hi).all());
    }

    #[test]
    fn polar_decomposition() {
        let r = Quat::from_rotation_y(0.7) * Quat::from_rotation_x(-0.2);
        let m = Mat3::from_quat(r) * Mat3::from_diagonal(Vec3::new(1.0, 2.0, 3.0));
        let (q, s) = polar(m);
        assert!(q.dot(r).abs() > 1.0 - 1e-5, "{q} {r}");
        assert!((s - 2.0).abs() < 1e-5);
        let (q, s) = polar(-Mat3::IDENTITY * 2.0);
        assert!(q.dot(Quat::IDENTITY).abs() > 1.0 - 1e-6 && (s + 2.0).abs() < 1e-6);
    }
}
