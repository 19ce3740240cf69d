//! Light sources, as the scene describes them.

use glam::{Mat3, Vec3};

/// An emitter.
#[derive(Debug, Clone, PartialEq)]
pub enum Emitter {
    /// An isotropic point light. Mitsuba `point` (`position` or `to_world`, `intensity`
    /// in W/sr); Nori `point` (`position`, `power` in W: intensity = power / 4π).
    Point { position: Vec3, intensity: Vec3 },
    /// A spot light at `position` shining along `axis` (Mitsuba `spot`: `intensity`
    /// in W/sr on the axis, `cutoff_angle` (degrees, default 20), `beam_width`
    /// (degrees, default 3/4 of the cutoff), `to_world` placing the light at its
    /// origin looking down its +z). Full intensity inside the beam width, falling
    /// linearly in angle to 0 at the cutoff, as Mitsuba's spotlight.
    ///
    /// ```xml
    /// <emitter type="spot"><transform name="to_world"><lookat origin="0,5,0" target="0,0,0"/></transform>
    ///     <rgb name="intensity" value="10"/><float name="cutoff_angle" value="30"/></emitter>
    /// ```
    Spot {
        position: Vec3,
        axis: Vec3,
        intensity: Vec3,
        cutoff_deg: f32,
        beam_width_deg: f32,
    },
    /// Uniform emission from the surface of the shape that carries it (front side).
    /// Mitsuba and Nori `area` (`radiance`).
    Area { radiance: Vec3 },
    /// Uniform radiance arriving from every direction at infinity. Mitsuba `constant`
    /// (`radiance`); Nori's `distantdisk` with `thetaA` = 180 is the same light.
    Constant { radiance: Vec3 },
    /// An area emitter whose radiance is a texture at the surface's uv times `scale`:
    /// Mitsuba `area` with a nested (or referenced) `<texture name="radiance">`.
    /// A bitmap on a rectangle (any mesh whose uv map is one affine map of the unit
    /// square) or a sphere has its points drawn by the texture's luminance, as Mitsuba
    /// does (`scene::textured_emitter`); other textures and shapes are sampled
    /// uniformly by area and weighted by the texture. Photon emission always samples
    /// by area.
    /// `<emitter type="area"><texture type="checkerboard" name="radiance"><rgb name="color0" value="8"/></texture></emitter>`
    TexturedArea { texture: u32, scale: Vec3 },
    /// Mitsuba `envmap`: radiance from a lat-long image at infinity (`filename`: EXR,
    /// Radiance HDR, or PNG/JPEG as sRGB), times `scale` (1), turned by `to_world` (a
    /// rotation). Convention and sampling in `scene::envmap`. `texture` is the image,
    /// a bitmap among the scene's textures.
    /// `<emitter type="envmap"><string name="filename" value="sky.exr"/><float name="scale" value="2"/></emitter>`
    EnvMap {
        texture: u32,
        scale: f32,
        to_world: Mat3,
        /// wavetrace's `sampling` parameter: `importance` (default) or `uniform`
        /// (sin θ-weighted cells only: uniform over the sphere, for comparisons).
        importance: bool,
    },
}
