//! Microfacet parameters shared by the rough models (Mitsuba's
//! `include/mitsuba/render/microfacet.h`): the `distribution` and `alpha` /
//! `alpha_u` + `alpha_v` parameters, and host-side reference integrals of the
//! distributions (the GLSL is `shaders/bsdf/microfacet.glsl`).

use glam::DVec3;

use super::fresnel::fresnel_dielectric;
use crate::gpu::layout::{BSDF_BECKMANN, BSDF_GGX};
use crate::scene::plugin::Param;
use crate::scene::properties::Properties;
use crate::scene::Error;

// The parameters of the rough models, as Mitsuba's `MicrofacetDistribution` reads them.
pub(super) const DISTRIBUTION: Param = Param::new(
    "distribution",
    "string",
    "beckmann",
    "microfacet distribution: beckmann or ggx",
);
pub(super) const ALPHA: Param = Param::new(
    "alpha",
    "float|texture",
    "0.1",
    "roughness (RMS slope), at least 1e-4",
);
pub(super) const ALPHA_U: Param = Param::new(
    "alpha_u",
    "float|texture",
    "",
    "anisotropic roughness along the tangent (with alpha_v, instead of alpha)",
)
.with("alpha_v");
pub(super) const ALPHA_V: Param = Param::new(
    "alpha_v",
    "float|texture",
    "",
    "anisotropic roughness along the bitangent (with alpha_u)",
)
.with("alpha_u");
pub(super) const SAMPLE_VISIBLE: Param = Param::new(
    "sample_visible",
    "boolean",
    "true",
    "accepted; GGX always samples visible normals, Beckmann never",
);

/// Microfacet normal distribution (`distribution` parameter).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Distribution {
    /// Beckmann (Walter et al. 2007, eq. 25); sampled by its full distribution D cos θm.
    Beckmann,
    /// GGX / Trowbridge-Reitz (Walter et al. 2007, eq. 33); visible normals sampled
    /// (Heitz 2018).
    Ggx,
}

pub(super) fn check_alpha(props: &Properties, key: &str, alpha: f32) -> Result<(), Error> {
    if !(alpha >= 0.0 && alpha.is_finite()) {
        return Err(props.error(
            key,
            format!(
                "roughness '{key}' of {} must be a finite number >= 0, found {alpha}",
                props.object()
            ),
        ));
    }
    Ok(())
}

/// `distribution`, and `alpha` or `alpha_u` + `alpha_v` (Mitsuba's microfacet.h).
/// Returns (distribution, alpha_u, alpha_v), each alpha at least 1e-4 as in Mitsuba.
pub(super) fn microfacet_params(
    props: &Properties,
    anisotropic: bool,
) -> Result<(Distribution, f32, f32), Error> {
    let distribution = match props
        .string("distribution", "beckmann")?
        .to_lowercase()
        .as_str()
    {
        "beckmann" => Distribution::Beckmann,
        "ggx" => Distribution::Ggx,
        other => {
            return Err(props.error(
                "distribution",
                format!("invalid distribution '{other}', must be 'beckmann' or 'ggx'"),
            ))
        }
    };
    props.boolean("sample_visible", true)?;
    let has_uv = props.has("alpha_u") || props.has("alpha_v");
    let (au, av) = if props.has("alpha") {
        if has_uv {
            return Err(props.error("alpha", "give either 'alpha' or 'alpha_u' and 'alpha_v'"));
        }
        let a = props.float("alpha", 0.1)?;
        check_alpha(props, "alpha", a)?;
        (a, a)
    } else if has_uv {
        if !anisotropic {
            return Err(props.error(
                if props.has("alpha_u") {
                    "alpha_u"
                } else {
                    "alpha_v"
                },
                format!("{} does not support anisotropic roughness", props.object()),
            ));
        }
        let (Some(au), Some(av)) = (props.float_opt("alpha_u")?, props.float_opt("alpha_v")?)
        else {
            return Err(props.object_error("both 'alpha_u' and 'alpha_v' must be given"));
        };
        check_alpha(props, "alpha_u", au)?;
        check_alpha(props, "alpha_v", av)?;
        (au, av)
    } else {
        (0.1, 0.1)
    };
    Ok((distribution, au.max(1e-4), av.max(1e-4)))
}

pub(super) fn distribution_id(d: Distribution) -> u32 {
    match d {
        Distribution::Beckmann => BSDF_BECKMANN,
        Distribution::Ggx => BSDF_GGX,
    }
}

/// Smith G1 for an isotropic distribution (as microfacet.glsl).
pub(super) fn smith_g1(d: Distribution, alpha: f64, v: DVec3, m: DVec3) -> f64 {
    if v.dot(m) * v.z <= 0.0 {
        return 0.0;
    }
    let xy = alpha * alpha * (v.x * v.x + v.y * v.y);
    if xy == 0.0 {
        return 1.0;
    }
    let tan2 = xy / (v.z * v.z);
    match d {
        Distribution::Beckmann => {
            let a = 1.0 / tan2.sqrt();
            if a >= 1.6 {
                1.0
            } else {
                (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
            }
        }
        Distribution::Ggx => 2.0 / (1.0 + (1.0 + tan2).sqrt()),
    }
}

/// Directional albedo of rough dielectric reflection (no refraction) at cos θ = mu:
/// R(μ) = ∫ F D G / (4 μ) dωo, integrated over microfacet normals drawn with density
/// D(m) cos θm (Walter 2007, eq. 28) on a 128 x 128 midpoint grid of the unit square,
/// where the integrand is F G (wo·m) / (μ cos θm).
pub fn rough_reflectance(d: Distribution, alpha: f64, mu: f64, eta: f64) -> f64 {
    const N: usize = 128;
    let wo = DVec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let mut sum = 0.0;
    for i in 0..N {
        let u1 = (i as f64 + 0.5) / N as f64;
        let tan2 = match d {
            Distribution::Beckmann => -alpha * alpha * (1.0 - u1).ln(),
            Distribution::Ggx => alpha * alpha * u1 / (1.0 - u1),
        };
        let cos_t = 1.0 / (1.0 + tan2).sqrt();
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        for j in 0..N {
            let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / N as f64;
            let m = DVec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
            let wom = wo.dot(m);
            if wom <= 0.0 {
                continue;
            }
            let wi = 2.0 * wom * m - wo;
            if wi.z <= 0.0 {
                continue;
            }
            let g = smith_g1(d, alpha, wo, m) * smith_g1(d, alpha, wi, m);
            sum += fresnel_dielectric(wom, eta) * g * wom / (mu * cos_t);
        }
    }
    sum / (N * N) as f64
}
