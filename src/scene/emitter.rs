//! Light sources, as the scene describes them.

use glam::Vec3;

/// An emitter.
#[derive(Debug, Clone, PartialEq)]
pub enum Emitter {
    /// An isotropic point light. Mitsuba `point` (`position` or `to_world`, `intensity`
    /// in W/sr); Nori `point` (`position`, `power` in W: intensity = power / 4π).
    Point { position: Vec3, intensity: Vec3 },
    /// Uniform emission from the surface of the shape that carries it (front side).
    /// Mitsuba and Nori `area` (`radiance`).
    Area { radiance: Vec3 },
    /// Uniform radiance arriving from every direction at infinity. Mitsuba `constant`
    /// (`radiance`); Nori's `distantdisk` with `thetaA` = 180 is the same light.
    Constant { radiance: Vec3 },
}
