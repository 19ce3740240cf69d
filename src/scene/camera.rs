//! The perspective camera.

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
}

impl Camera {
    /// tan of half the horizontal and vertical fields of view (`Frame::tan_half_fov`,
    /// as shaders/sensor/camera.glsl spans the film).
    pub fn tan_half_fov(&self) -> [f32; 2] {
        let tan_x = (self.fov_x_deg.to_radians() * 0.5).tan();
        [tan_x, tan_x * self.height as f32 / self.width as f32]
    }
}
