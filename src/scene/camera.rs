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
}

impl Projection {
    /// `CAMERA_*` of `Frame::camera_kind`, aperture radius and focus distance.
    pub fn frame_fields(&self) -> (u32, f32, f32) {
        use crate::gpu::layout::{
            CAMERA_ORTHOGRAPHIC, CAMERA_PERSPECTIVE, CAMERA_RADIANCEMETER, CAMERA_THINLENS,
        };
        match *self {
            Projection::Perspective => (CAMERA_PERSPECTIVE, 0.0, 0.0),
            Projection::Orthographic => (CAMERA_ORTHOGRAPHIC, 0.0, 0.0),
            Projection::RadianceMeter => (CAMERA_RADIANCEMETER, 0.0, 0.0),
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
