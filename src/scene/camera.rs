//! The camera: perspective (a pinhole), orthographic or a thin lens.

use glam::Mat4;

/// A pinhole perspective camera.
///
/// Camera space follows Mitsuba and Nori: the camera looks down +Z, +Y is up and +X
/// points to the *left* of the image, so image column 0 maps to camera +X.
///
/// Mitsuba: `<sensor type="perspective">` with `fov`, `fov_axis` (x, y, diagonal,
/// smaller, larger; default x) or instead `focal_length` (35 mm film, default "50mm"), `near_clip` (1e-2), `far_clip` (1e4), `to_world`, and
/// nested `<film>` (width, height; default 768x576) and `<sampler>` (sample_count).
/// Nori: `<camera type="perspective">` with `fov` (horizontal), `width`, `height`
/// (default 1280x720), `nearClip`, `farClip`, `toWorld`.
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    /// Camera-to-world transform (may contain scale or a mirror).
    pub to_world: Mat4,
    /// Horizontal field of view in degrees, after resolving `fov_axis` with the film's
    /// aspect ratio.
    pub fov_x_deg: f32,
    pub near_clip: f32,
    pub far_clip: f32,
    pub width: u32,
    pub height: u32,
    /// How rays leave the camera.
    pub projection: Projection,
    /// Mitsuba's `batch` sensor: its child cameras side by side, each `width / n`
    /// pixels wide (child i renders columns [i w / n, (i + 1) w / n)); empty for one
    /// camera. The fields above are then child 0's, on the whole film.
    pub batch: Vec<Camera>,
}

/// How a camera makes rays (shaders/sensor/camera.glsl).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Projection {
    /// A pinhole: Mitsuba `perspective`, Nori `perspective`.
    #[default]
    Perspective,
    /// Parallel rays along +z from the film rectangle x ∈ [-1, 1], y ∈ [-1/a, 1/a]
    /// (a the aspect ratio) on the near plane, before `to_world`: Mitsuba
    /// `orthographic` (`fov_x_deg` unused).
    Orthographic,
    /// A thin lens (Mitsuba `thinlens`): rays from a uniform point of the disk of
    /// radius `aperture_radius` through the point the pinhole ray meets at depth
    /// `focus_distance`.
    ThinLens {
        aperture_radius: f32,
        focus_distance: f32,
    },
    /// One ray from the origin of `to_world` along its +z, for every pixel: Mitsuba
    /// `radiancemeter`.
    RadianceMeter,
    /// Radiance leaving the scene along -(to_world's +z), Mitsuba `distant`: rays along
    /// +z from a uniform point of the scene's bounding sphere's cross-section, or
    /// aimed at `target` (render::plan sets the frame's camera_to_world from the
    /// scene's bounds).
    Distant { target: Option<glam::Vec3> },
    /// The irradiance over a shape, Mitsuba `irradiancemeter` (nested in the shape):
    /// rays from a uniform point of the shape's surface (drawn by the film position,
    /// as Mitsuba's sample_position) in a cosine-weighted direction about its normal,
    /// each weighted by π (`to_world` unused).
    IrradianceMeter { shape: SensorShape },
}

/// The shape an `irradiancemeter` sits on: a mesh or a quadric, by its index in
/// `Scene::meshes` or `Scene::quadrics`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SensorShape {
    Mesh(u32),
    Quadric(u32),
}

impl Projection {
    /// The frame's camera_to_world of a `distant` sensor looking along `d` (unit) at
    /// a scene bounded by the sphere (`center`, `radius`): camera.glsl's ray starts at
    /// M (x, y, -1, 1) for (x, y) on the unit disk and runs along M's +z, so the
    /// columns are R s, R t, R d, c (s, t ⟂ d) without a target, and 0, 0, 2R d,
    /// target with one (Mitsuba's distant sample_ray).
    pub fn distant_frame(
        d: glam::Vec3,
        target: Option<glam::Vec3>,
        center: glam::Vec3,
        radius: f32,
    ) -> glam::Mat4 {
        use glam::Vec4;
        // Mitsuba widens the sphere by its ray epsilon.
        let r = (radius * (1.0 + 1e-4)).max(1e-4);
        match target {
            Some(p) => Mat4::from_cols(
                Vec4::ZERO,
                Vec4::ZERO,
                (2.0 * r * d).extend(0.0),
                p.extend(1.0),
            ),
            None => {
                let s = d.any_orthonormal_vector();
                let t = d.cross(s);
                Mat4::from_cols(
                    (r * s).extend(0.0),
                    (r * t).extend(0.0),
                    (r * d).extend(0.0),
                    center.extend(1.0),
                )
            }
        }
    }

    /// Whether this is a thin lens (the particle tracer's PTRACER_THIN_LENS).
    pub fn is_thin_lens(&self) -> bool {
        matches!(self, Projection::ThinLens { .. })
    }

    /// `CAMERA_*` of `Frame::camera_kind`, aperture radius and focus distance.
    pub fn frame_fields(&self) -> (u32, f32, f32) {
        use crate::gpu::layout::{
            CAMERA_DISTANT, CAMERA_IRRADIANCEMETER, CAMERA_ORTHOGRAPHIC, CAMERA_PERSPECTIVE,
            CAMERA_RADIANCEMETER, CAMERA_THINLENS,
        };
        match *self {
            Projection::Perspective => (CAMERA_PERSPECTIVE, 0.0, 0.0),
            Projection::Orthographic => (CAMERA_ORTHOGRAPHIC, 0.0, 0.0),
            Projection::RadianceMeter => (CAMERA_RADIANCEMETER, 0.0, 0.0),
            Projection::Distant { .. } => (CAMERA_DISTANT, 0.0, 0.0),
            Projection::IrradianceMeter { .. } => (CAMERA_IRRADIANCEMETER, 0.0, 0.0),
            Projection::ThinLens {
                aperture_radius,
                focus_distance,
            } => (CAMERA_THINLENS, aperture_radius, focus_distance),
        }
    }
}

impl Camera {
    /// tan of half the horizontal and vertical fields of view (`Frame::tan_half_fov`,
    /// as shaders/sensor/camera.glsl spans the film).
    pub fn tan_half_fov(&self) -> [f32; 2] {
        let tan_x = (self.fov_x_deg.to_radians() * 0.5).tan();
        [tan_x, tan_x * self.height as f32 / self.width as f32]
    }
}
