//! Surface scattering models, as the scene describes them.

use glam::Vec3;

/// A BSDF. More models arrive with the surface-transport work; every shape has one.
#[derive(Debug, Clone, PartialEq)]
pub enum Bsdf {
    /// Lambertian reflection. Mitsuba `diffuse` (`reflectance`, default 0.5); Nori
    /// `diffuse` (`albedo`, default 0.5). A Mitsuba `twosided` around one BSDF is
    /// unwrapped to that BSDF for now.
    Diffuse { reflectance: Vec3 },
}

impl Default for Bsdf {
    fn default() -> Self {
        Bsdf::Diffuse {
            reflectance: Vec3::splat(0.5),
        }
    }
}
