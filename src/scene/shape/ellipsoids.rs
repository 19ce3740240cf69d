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

use std::path::{Path, PathBuf};

use glam::{Mat3, Quat, Vec3};

use super::{Geometry, Mesh, TO_WORLD};
use crate::scene::builder;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::ply;
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "ellipsoids",
    "A cloud of anisotropic ellipsoids (centre, log-scales, rotation quaternion) from a PLY file, intersected in closed form, back faces culled; uv = 0. Only the `filename` form (Mitsuba's `data`/`centers` tensors cannot be written in XML); no area emitters or media on them yet; attributes other than the geometry are ignored.",
    &[
        FILENAME,
        EXTENT,
        SCALE_FACTOR,
        ELLIPSOIDS_TO_WORLD,
    ],
);

/// The parameters `ellipsoids` shares with `ellipsoidsmesh` (which reads the same file
/// through [`world`]).
pub const FILENAME: Param = Param::new(
    "filename",
    "string",
    "",
    "the PLY file: `x y z nx ny nz` first, `scale_0..2 rot_0..3` last (required)",
);
pub const EXTENT: Param = Param::new(
    "extent",
    "float",
    "3",
    "the semi-axes are the file's scales times this",
);
pub const SCALE_FACTOR: Param = Param::new(
    "scale_factor",
    "float",
    "1",
    "a factor on every ellipsoid's scales",
);
pub const ELLIPSOIDS_TO_WORLD: Param = Param::new(
    "to_world",
    TO_WORLD.ty,
    TO_WORLD.default,
    "moves the centres, rotates the ellipsoids and scales them by its mean scale",
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
    let (path, ellipsoids) = world(el, props)?;
    let mut mesh = Mesh {
        name: path.display().to_string(),
        ..Mesh::default()
    };
    for (k, e) in ellipsoids.into_iter().enumerate() {
        mesh.positions.push(e.center);
        mesh.radii.push(e.scale.abs().max_element());
        mesh.indices.push([k as u32, MARKER, 0]);
        mesh.ellipsoids.push(e);
    }
    Ok(Geometry::Curves {
        mesh,
        to_world: glam::Mat4::IDENTITY,
    })
}

/// The file and the ellipsoids in world space of an `ellipsoids` or `ellipsoidsmesh`
/// (their parameters `filename`, `extent`, `scale_factor`, `to_world` and refusals).
pub fn world(el: &Element, props: &Properties) -> Result<(PathBuf, Vec<Ellipsoid>), Error> {
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
    let raw = parse(&path)?;
    let mut out = Vec::with_capacity(raw.len());
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
        out.push(ell);
    }
    Ok((path, out))
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
/// `rot_0` its real part), before `to_world`, exp and `extent`. The file is read by
/// [`ply::first_element`]; here only Mitsuba's layout is checked (ellipsoids.h).
pub fn parse(path: &Path) -> Result<Vec<Ellipsoid>, Error> {
    const FIRST: [&str; 6] = ["x", "y", "z", "nx", "ny", "nz"];
    const LAST: [&str; 7] = [
        "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3",
    ];
    let table = ply::first_element(path, "ellipsoid", |names| {
        let n = names.len();
        if n < 13 || names[..6] != FIRST || names[n - 7..] != LAST {
            return Err(format!(
                "ellipsoids need the properties 'x y z nx ny nz' first and 'scale_0 scale_1 scale_2 rot_0 rot_1 rot_2 rot_3' last (Mitsuba's layout); this file has '{}'",
                names.join(" ")
            ));
        }
        // The centre, then the scales and the quaternion.
        Ok((0..3).chain(n - 7..n).collect())
    })?;
    let mut out = Vec::with_capacity(table.count());
    for k in 0..table.count() {
        let v = table.entry(k);
        let rotation = Quat::from_xyzw(v[7], v[8], v[9], v[6]);
        if rotation.length_squared() == 0.0 {
            return Err(table.error_at(
                path,
                k,
                format!("ellipsoid {k}: its quaternion 'rot_0..3' is zero"),
            ));
        }
        out.push(Ellipsoid {
            center: Vec3::new(v[0], v[1], v[2]),
            scale: Vec3::new(v[3], v[4], v[5]),
            rotation,
        });
    }
    if out.is_empty() {
        return Err(Error::file(path, "the file holds no ellipsoids"));
    }
    Ok(out)
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

    fn read(bytes: impl AsRef<[u8]>) -> Result<Vec<Ellipsoid>, Error> {
        let path = crate::scene::testutil::temp_dir("ellipsoids").join("e.ply");
        std::fs::write(&path, bytes).unwrap();
        parse(&path)
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
        assert_eq!(read(&bin).unwrap(), e);
        let mut big = HEADER.replace("ascii", "binary_big_endian").into_bytes();
        for v in [1f32, 2., 3., 0., 0., 1., 0.5, 0., 0.5, -1., 1., 0., 0., 0.] {
            big.extend_from_slice(&v.to_be_bytes());
        }
        for v in [0f32, 0., 0., 0., 0., 0., 1., 0., 0., 0., 0.5, 0.5, 0.5, 0.5] {
            big.extend_from_slice(&v.to_be_bytes());
        }
        assert_eq!(read(&big).unwrap(), e);
    }

    #[test]
    fn errors_name_the_cause() {
        let msg = |t: &[u8]| read(t).unwrap_err().to_string();
        let ascii = |rows: &str| msg(format!("{HEADER}{rows}").as_bytes());
        // The header is 18 lines: entry k is on line 19 + k.
        let e = ascii("1 2 3 0 0 1 0.5 0 0.5 nan 1 0 0 0\n0 0 0 0 0 0 1 0 0 0 1 0 0 0\n");
        assert!(
            e.contains("e.ply:19: ellipsoid 0: 'scale_2' is not finite ('nan')"),
            "{e}"
        );
        let e = ascii("1 2 3 0 0 1 0.5 0 0.5 0 1 0 0 0\n0 0 0 0 0 0 1 0 0 1e99 1 0 0 0\n");
        assert!(
            e.contains("e.ply:20: ellipsoid 1: 'scale_2' is not finite (inf)"),
            "{e}"
        );
        let e = ascii("1 2 3 0 0 1 0.5 0 0.5 0 1 0 0 0\n0 0 0 0 0 0 abc 0 0 0 1 0 0 0\n");
        assert!(
            e.contains("e.ply:20: ellipsoid 1: 'opacity' is not a number"),
            "{e}"
        );
        let e = ascii("1 2 3 0 0 1 0.5 0 0.5 0 1 0 0 0\n0 0 0 0 0 0 1 0 0 0 1\n");
        assert!(
            e.contains("e.ply:20: ellipsoid 1: the line ends before 'rot_1'"),
            "{e}"
        );
        assert!(ascii("1 2 3 0 0 1 0.5 0 0.5 0 1 0 0 0\n")
            .contains("e.ply: the file ends inside ellipsoid 1 of 2"));
        assert!(msg(HEADER.replace("scale_0", "s0").as_bytes()).contains("'x y z nx ny nz' first"));
        let e = ascii("1 2 3 0 0 1 0.5 0 0.5 0 1 0 0 0\n0 0 0 0 0 0 1 0 0 0 0 0 0 0\n");
        assert!(e.contains("e.ply:20: ellipsoid 1: its quaternion"), "{e}");
        assert!(msg(b"hello\n").contains("end_header"));
        // Binary: the entry, no line.
        let binary = |rows: &[[f32; 14]]| {
            let mut b = HEADER.replace("ascii", "binary_little_endian").into_bytes();
            for v in rows.iter().flatten() {
                b.extend_from_slice(&v.to_le_bytes());
            }
            b
        };
        let good = [1f32, 2., 3., 0., 0., 1., 0.5, 0., 0.5, -1., 1., 0., 0., 0.];
        let mut nan = good;
        nan[11] = f32::NAN;
        let e = msg(&binary(&[good, nan]));
        assert!(
            e.contains("e.ply: ellipsoid 1: 'rot_1' is not finite (NaN)"),
            "{e}"
        );
        let b = binary(&[good, good]);
        let e = msg(&b[..b.len() - 3]);
        assert!(
            e.contains("e.ply: the file ends inside ellipsoid 1 of 2"),
            "{e}"
        );
        let mut zero = good;
        zero[10..].fill(0.0);
        assert!(msg(&binary(&[zero, good])).contains("ellipsoid 0: its quaternion"));
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
