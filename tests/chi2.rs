//! Chi-square goodness-of-fit tests of every GLSL sampler against its own pdf
//! (tests/common/stats.rs explains the method): the warps of warp.glsl, the microfacet
//! normal samplers of microfacet.glsl, and bsdf_sample against bsdf_pdf for every BSDF
//! over several (wo, parameters). Each BSDF case also checks that the pdf integrates
//! to 1 minus the probability of delta lobes, that sample's pdf equals bsdf_pdf and
//! that its weight equals bsdf_eval / bsdf_pdf.

mod common;

use common::stats::{
    bsdf_probe, dir, warp_probe, BsdfProbe, Warp, WarpProbe, FLAG_DELTA, FLAG_REFLECTION,
};
use glam::{Vec2, Vec3};
use wavetrace::gpu::layout::BsdfRecord;
use wavetrace::scene::bsdf::{
    fresnel_dielectric, Bsdf, Conductor, Dielectric, Diffuse, Distribution, NoriMicrofacet,
    PPlastic, Plastic, Principled, RoughConductor, RoughDielectric, RoughPlastic,
};
use wavetrace::warptest::{test_bsdf, test_warp, Axis, Outcome};

/// At least as many chi-square tests as this file runs (113 now; Šidák correction, a
/// larger m only makes each test slightly more lenient).
const TESTS_IN_FILE: usize = 126;
/// Family-wise significance of the file.
const ALPHA: f64 = 0.01;

/// Samples per chi-square test: enough that a pdf 2% off in a cell of 1% mass shows.
const N: u32 = 400_000;

fn assert_outcome(name: &str, outcome: &Outcome) {
    common::stats::assert_outcome(name, outcome, ALPHA, TESTS_IN_FILE);
}

/// A warp against its own pdf (wavetrace::warptest::test_warp): a 32 x 32 chart of
/// the planar domains, a 32 x 24 sphere grid for directions.
fn warp_case(probe: &WarpProbe, name: &str, warp: Warp, seed: u32) {
    let outcome = test_warp(probe, warp, N, seed).expect("warp kernel");
    if warp.spherical() {
        let samples = probe.sample(warp, 1024, seed).expect("warp kernel");
        for s in samples {
            let d = Vec3::new(s[0], s[1], s[2]);
            assert!(
                (d.length() - 1.0).abs() < 1e-4,
                "{name}: sample {d} is not unit"
            );
        }
    }
    // Constant densities with affine Jacobians (planar): the midpoint rule is exact to
    // rounding. Smooth densities with 256 x 192 points: error well under 0.5%; the
    // cap's edge cuts one ring of cells (< 0.5% of its mass).
    let tolerance = if warp.spherical() { 5e-3 } else { 1e-3 };
    let total = outcome.pdf_integral;
    assert!(
        (total - 1.0).abs() < tolerance,
        "{name}: pdf integrates to {total}"
    );
    assert_outcome(name, &outcome);
}

#[test]
fn warps() {
    let probe = warp_probe();
    warp_case(&probe, "square to disk", Warp::Disk, 1);
    warp_case(&probe, "uniform triangle", Warp::Triangle, 1);
    warp_case(&probe, "uniform hemisphere", Warp::UniformHemisphere, 2);
    warp_case(&probe, "cosine hemisphere", Warp::CosineHemisphere, 2);
    warp_case(&probe, "uniform sphere", Warp::UniformSphere, 2);
    // Cap edges on ring boundaries of the 32-ring grid (θ = (π/2) (2i/32)², i = 14 and
    // 5), so no cell straddles the jump of the density; 1e-4 inside, so that f32
    // rounding cannot push a sample over the boundary.
    for i in [14.0f64, 5.0] {
        let cos_max = (0.5 * std::f64::consts::PI * (i / 16.0) * (i / 16.0) - 1e-4).cos() as f32;
        warp_case(
            &probe,
            &format!("spherical cap cos θmax = {cos_max}"),
            Warp::Cap { cos_max },
            2,
        );
    }
}

/// The sampling routines of sensors and emitters: the thin lens's aperture, a
/// projector's photon directions (uniform image points through the plane z = 1).
#[test]
fn sensor_and_emitter_warps() {
    let probe = warp_probe();
    warp_case(&probe, "thin-lens aperture", Warp::ThinLensAperture, 3);
    for (tan_x, tan_y) in [(1.2, 0.8), (0.3, 0.5)] {
        warp_case(
            &probe,
            &format!("projector, tan half fov {tan_x} x {tan_y}"),
            Warp::Projector { tan_x, tan_y },
            3,
        );
    }
}

/// The test can fail: cosine-weighted samples against the uniform hemisphere's pdf
/// (the test-only warp) are rejected with overwhelming significance.
#[test]
fn a_wrong_pdf_is_rejected() {
    let probe = warp_probe();
    let outcome = test_warp(&probe, Warp::MismatchedCosine, N, 2).expect("warp kernel");
    assert!(
        outcome.chi2.p_value < 1e-12,
        "a mismatched pdf passed: p = {}",
        outcome.chi2.p_value
    );
}

#[test]
fn microfacet_normals() {
    let probe = warp_probe();
    for (ty, name) in [(0u32, "beckmann"), (1, "ggx")] {
        for (au, av) in [(0.1f32, 0.1f32), (0.5, 0.5), (0.15, 0.6)] {
            // Beckmann samples D cos θm whatever wo; GGX visible normals depend on wo.
            let wos: &[Vec3] = if ty == 0 {
                &[Vec3::Z]
            } else {
                &[Vec3::Z, dir(45.0, 30.0), dir(85.0, 200.0)]
            };
            for &wo in wos {
                warp_case(
                    &probe,
                    &format!("{name} normals α = ({au}, {av}), wo = {wo:.2}"),
                    Warp::Microfacet {
                        distribution: ty,
                        alpha_u: au,
                        alpha_v: av,
                        wo,
                    },
                    2,
                );
            }
        }
    }
}

/// One BSDF case: chi-square of the non-delta samples against bsdf_pdf, pdf
/// normalization, consistency (common::stats::bsdf_case).
fn bsdf_case(probe: &BsdfProbe, name: &str, bsdf: &Bsdf, wo: Vec3, axis: Axis, seed: u32) {
    let rec = BsdfRecord::from(bsdf);
    let recs = std::slice::from_ref(&rec);
    common::stats::bsdf_case(probe, name, recs, wo, axis, (N, seed), ALPHA, TESTS_IN_FILE);
}

fn conductor_none() -> (Vec3, Vec3) {
    (Vec3::ZERO, Vec3::ONE)
}

#[test]
fn rough_conductors() {
    let probe = bsdf_probe();
    let (eta, k) = (Vec3::new(0.2, 0.92, 1.1), Vec3::new(3.9, 2.46, 2.14)); // Cu
    for distribution in [Distribution::Beckmann, Distribution::Ggx] {
        for (au, av) in [(0.05, 0.05), (0.3, 0.3), (0.8, 0.8), (0.1, 0.5)] {
            let b = Bsdf::RoughConductor(RoughConductor {
                distribution,
                alpha_u: au,
                alpha_v: av,
                eta,
                k,
                specular_reflectance: Vec3::ONE,
            });
            for wo in [dir(10.0, 20.0), dir(70.0, 120.0)] {
                let axis = if au < 0.2 {
                    Axis::Reflect
                } else {
                    Axis::Normal
                };
                bsdf_case(
                    &probe,
                    &format!("roughconductor {distribution:?} α = ({au}, {av})"),
                    &b,
                    wo,
                    axis,
                    3,
                );
            }
        }
    }
    let _ = conductor_none();
}

#[test]
fn rough_dielectrics() {
    let probe = bsdf_probe();
    for distribution in [Distribution::Beckmann, Distribution::Ggx] {
        for (au, av) in [(0.1f32, 0.1f32), (0.3, 0.3), (0.8, 0.8), (0.15, 0.45)] {
            for eta in [1.5f32, 1.0 / 1.5] {
                let b = Bsdf::RoughDielectric(RoughDielectric {
                    distribution,
                    alpha_u: au,
                    alpha_v: av,
                    eta,
                    specular_reflectance: Vec3::ONE,
                    specular_transmittance: Vec3::ONE,
                });
                // From outside, and from inside (wo below the surface).
                for wo in [dir(30.0, 40.0), dir(150.0, 250.0)] {
                    let axis = if au < 0.2 {
                        Axis::Refract(eta)
                    } else {
                        Axis::Normal
                    };
                    bsdf_case(
                        &probe,
                        &format!("roughdielectric {distribution:?} α = ({au}, {av}) η = {eta:.3}"),
                        &b,
                        wo,
                        axis,
                        4,
                    );
                }
            }
        }
    }
}

#[test]
fn diffuse_plastics_and_nori() {
    let probe = bsdf_probe();
    let diffuse = Bsdf::Diffuse(Diffuse {
        reflectance: Vec3::new(0.2, 0.5, 0.8),
    });
    bsdf_case(&probe, "diffuse", &diffuse, dir(40.0, 0.0), Axis::Normal, 5);
    let twosided = Bsdf::TwoSided(Box::new(Bsdf::RoughConductor(RoughConductor {
        distribution: Distribution::Ggx,
        alpha_u: 0.3,
        alpha_v: 0.3,
        eta: Vec3::ZERO,
        k: Vec3::ONE,
        specular_reflectance: Vec3::ONE,
    })));
    bsdf_case(
        &probe,
        "twosided roughconductor (back face)",
        &twosided,
        dir(130.0, 60.0),
        Axis::Normal,
        6,
    );
    for (eta, nonlinear) in [(1.49f32, false), (1.9, true)] {
        let b = Bsdf::Plastic(Plastic {
            diffuse_reflectance: Vec3::new(0.1, 0.27, 0.36),
            specular_reflectance: Vec3::ONE,
            eta,
            nonlinear,
        });
        for wo in [dir(20.0, 10.0), dir(80.0, 100.0)] {
            bsdf_case(
                &probe,
                &format!("plastic η = {eta}"),
                &b,
                wo,
                Axis::Normal,
                7,
            );
        }
    }
    for distribution in [Distribution::Beckmann, Distribution::Ggx] {
        for alpha in [0.05f32, 0.3, 0.8] {
            let b = Bsdf::RoughPlastic(RoughPlastic {
                distribution,
                alpha,
                diffuse_reflectance: Vec3::new(0.6, 0.3, 0.2),
                specular_reflectance: Vec3::ONE,
                eta: 1.49,
                nonlinear: false,
            });
            for wo in [dir(15.0, 10.0), dir(75.0, 300.0)] {
                let axis = if alpha < 0.2 {
                    Axis::Reflect
                } else {
                    Axis::Normal
                };
                bsdf_case(
                    &probe,
                    &format!("roughplastic {distribution:?} α = {alpha}"),
                    &b,
                    wo,
                    axis,
                    8,
                );
            }
        }
    }
    for alpha in [0.1f32, 0.5] {
        let b = Bsdf::NoriMicrofacet(NoriMicrofacet {
            alpha,
            eta: 1.5046 / 1.000277,
            kd: Vec3::new(0.2, 0.2, 0.4),
        });
        for wo in [dir(25.0, 0.0), dir(70.0, 45.0)] {
            let axis = if alpha < 0.2 {
                Axis::Reflect
            } else {
                Axis::Normal
            };
            bsdf_case(
                &probe,
                &format!("nori microfacet α = {alpha}"),
                &b,
                wo,
                axis,
                9,
            );
        }
    }
}

/// Smooth models sample delta lobes only: exact mirror / refraction directions, the
/// reflected fraction follows Fresnel (binomial 5σ), weights as documented.
/// Mitsuba's `pplastic`: microfacet lobe with the fixed probability s / (d + s), else
/// cosine-weighted; both distributions, sharp, rough and anisotropic.
#[test]
fn pplastic() {
    let probe = bsdf_probe();
    for distribution in [Distribution::Beckmann, Distribution::Ggx] {
        for (au, av) in [(0.05f32, 0.05f32), (0.4, 0.4), (0.1, 0.5)] {
            let b = Bsdf::PPlastic(PPlastic {
                distribution,
                alpha_u: au,
                alpha_v: av,
                diffuse_reflectance: Vec3::new(0.6, 0.3, 0.2),
                specular_reflectance: Vec3::ONE,
                eta: 1.49,
            });
            for wo in [dir(15.0, 10.0), dir(75.0, 300.0)] {
                let axis = if au.max(av) < 0.2 {
                    Axis::Reflect
                } else {
                    Axis::Normal
                };
                bsdf_case(
                    &probe,
                    &format!("pplastic {distribution:?} α = ({au}, {av})"),
                    &b,
                    wo,
                    axis,
                    10,
                );
            }
        }
    }
}

/// Mitsuba's `principled` and `principledthin`: its lobe probabilities (diffuse,
/// clearcoat, GGX transmission and reflection; the thin sheet's four), from above, from
/// inside (principled) and from the other face (principledthin).
#[test]
fn principled() {
    use wavetrace::scene::bsdf::principled::{specular_to_eta, HAS_DIFF_TRANS, HAS_SPEC_TRANS};
    let probe = bsdf_probe();
    let coat = Principled {
        base_color: Vec3::new(0.2, 0.8, 0.1),
        roughness: 0.15,
        anisotropic: 0.8,
        metallic: 0.1,
        clearcoat: 0.9,
        sheen: 0.9,
        eta: specular_to_eta(0.7),
        ..Default::default()
    };
    let glass = Principled {
        base_color: Vec3::new(0.3, 0.6, 0.8),
        roughness: 0.3,
        anisotropic: 0.2,
        spec_trans: 0.7,
        clearcoat: 0.6,
        clearcoat_gloss: 0.5,
        sheen: 0.2,
        eta: specular_to_eta(0.4),
        has: HAS_SPEC_TRANS,
        ..Default::default()
    };
    let everything = Principled {
        base_color: Vec3::new(0.9, 0.5, 0.2),
        roughness: 0.6,
        metallic: 0.3,
        spec_tint: 0.4,
        sheen: 0.3,
        sheen_tint: 0.2,
        clearcoat: 0.6,
        clearcoat_gloss: 0.3,
        spec_trans: 0.4,
        flatness: 0.5,
        eta: 1.33,
        rates: [2.0, 0.5, 3.0, 1.0],
        has: HAS_SPEC_TRANS,
        ..Default::default()
    };
    let thin = Principled {
        thin: true,
        base_color: Vec3::new(0.7, 0.1, 0.1),
        anisotropic: 0.8,
        spec_trans: 0.8,
        diff_trans: 1.4,
        sheen: 0.8,
        eta: 1.33,
        has: HAS_SPEC_TRANS | HAS_DIFF_TRANS,
        ..Default::default()
    };
    let thin_sharp = Principled {
        thin: true,
        base_color: Vec3::new(0.2, 0.5, 0.9),
        roughness: 0.25,
        spec_trans: 0.5,
        spec_tint: 0.6,
        sheen: 0.4,
        flatness: 0.6,
        diff_trans: 0.4,
        eta: 1.6,
        rates: [2.0, 1.0, 1.0, 0.5],
        has: HAS_SPEC_TRANS | HAS_DIFF_TRANS,
        ..Default::default()
    };
    let below = |v: Vec3| Vec3::new(v.x, v.y, -v.z);
    let cases = [
        ("principled clearcoat", coat, dir(15.0, 10.0), Axis::Reflect),
        (
            "principled clearcoat",
            coat,
            dir(75.0, 300.0),
            Axis::Reflect,
        ),
        ("principled glass", glass, dir(40.0, 60.0), Axis::Normal),
        (
            "principled glass inside",
            glass,
            below(dir(30.0, 200.0)),
            Axis::Normal,
        ),
        (
            "principled every lobe",
            everything,
            dir(60.0, 120.0),
            Axis::Normal,
        ),
        (
            "principled every lobe inside",
            everything,
            below(dir(70.0, 20.0)),
            Axis::Normal,
        ),
        ("principledthin", thin, dir(30.0, 45.0), Axis::Normal),
        (
            "principledthin other face",
            thin,
            below(dir(50.0, 250.0)),
            Axis::Normal,
        ),
        (
            "principledthin sharp",
            thin_sharp,
            dir(20.0, 80.0),
            Axis::Normal,
        ),
        (
            "principledthin sharp",
            thin_sharp,
            below(dir(65.0, 10.0)),
            Axis::Normal,
        ),
        (
            "principled defaults",
            Principled::default(),
            dir(45.0, 0.0),
            Axis::Normal,
        ),
    ];
    for (name, b, wo, axis) in cases {
        bsdf_case(&probe, name, &Bsdf::Principled(b), wo, axis, 12);
    }
}

#[test]
fn smooth_delta_models() {
    let probe = bsdf_probe();
    let n = 200_000u32;
    for eta in [1.5f32, 1.0 / 1.5] {
        let b = Bsdf::Dielectric(Dielectric {
            eta,
            specular_reflectance: Vec3::ONE,
            specular_transmittance: Vec3::ONE,
        });
        for wo in [
            dir(0.0, 0.0),
            dir(35.0, 80.0),
            dir(60.0, 10.0),
            dir(140.0, 33.0),
            dir(170.0, 5.0),
        ] {
            let rec = BsdfRecord::from(&b);
            let samples = probe.sample(&rec, wo, n, 11).expect("bsdf kernel");
            let (eta_it, cos) = if wo.z > 0.0 {
                (eta, wo.z)
            } else {
                (1.0 / eta, -wo.z)
            };
            let f = fresnel_dielectric(cos as f64, eta_it as f64);
            let mut reflected = 0;
            for s in &samples {
                assert_ne!(s.flags & FLAG_DELTA, 0);
                assert_eq!((s.pdf, s.eval, s.pdf_eval), (0.0, Vec3::ZERO, 0.0));
                if s.flags & FLAG_REFLECTION != 0 {
                    reflected += 1;
                    assert!((s.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-5);
                    assert_eq!(s.weight, Vec3::ONE);
                } else {
                    assert!(s.wi.z * wo.z < 0.0, "refraction stays on its side");
                    // Snell: η_i sin θi = η_t sin θt, and radiance scaled by 1/η_it².
                    let sin_o = Vec2::new(wo.x, wo.y).length();
                    let sin_i = Vec2::new(s.wi.x, s.wi.y).length();
                    assert!((sin_o - eta_it * sin_i).abs() < 1e-5, "{wo} -> {}", s.wi);
                    assert!((s.weight - Vec3::splat(1.0 / (eta_it * eta_it))).length() < 1e-5);
                }
            }
            let frac = reflected as f64 / n as f64;
            let sigma = (f * (1.0 - f) / n as f64).sqrt();
            assert!(
                (frac - f).abs() <= 5.0 * sigma + 1e-6,
                "dielectric η = {eta}, wo = {wo}: reflected {frac}, Fresnel {f}"
            );
        }
    }
    // Conductors: gold at normal incidence reflects ((η-1)² + κ²) / ((η+1)² + κ²).
    let gold = Bsdf::Conductor(Conductor {
        eta: Vec3::new(0.1456, 0.3729, 1.4414),
        k: Vec3::new(3.9565, 2.3955, 1.6007),
        specular_reflectance: Vec3::ONE,
    });
    let s = probe
        .sample(&BsdfRecord::from(&gold), Vec3::Z, 64, 12)
        .expect("bsdf kernel");
    let want = |e: f32, k: f32| ((e - 1.0).powi(2) + k * k) / ((e + 1.0).powi(2) + k * k);
    let w = s[0].weight;
    assert!(
        (w.x - want(0.1456, 3.9565)).abs() < 1e-5 && (w.z - want(1.4414, 1.6007)).abs() < 1e-5,
        "{w}"
    );
    assert!(w.x > w.y && w.y > w.z, "gold is yellow: {w}");
    // A one-sided mirror seen from behind absorbs; twosided mirrors it.
    let (e, k) = conductor_none();
    let mirror = Bsdf::Conductor(Conductor {
        eta: e,
        k,
        specular_reflectance: Vec3::ONE,
    });
    let back = dir(120.0, 10.0);
    assert_eq!(
        probe
            .sample(&BsdfRecord::from(&mirror), back, 64, 13)
            .expect("bsdf kernel")[0]
            .flags,
        0
    );
    let s = probe
        .sample(
            &BsdfRecord::from(&Bsdf::TwoSided(Box::new(mirror))),
            back,
            64,
            13,
        )
        .expect("bsdf kernel")[0];
    assert!(
        (s.wi - Vec3::new(-back.x, -back.y, back.z)).length() < 1e-5
            && (s.weight - Vec3::ONE).length() < 1e-5
    );
}

/// Mitsuba's `hair` (Chiang et al. 2016): the lobe choice by attenuation, the
/// longitudinal and azimuthal samplers, over sharp and rough fibers, tilts, indices
/// and viewers on both sides; and a wrong pdf (the samples of a fiber with twice the
/// scale tilt against this one's pdf) is rejected.
#[test]
fn hair() {
    use wavetrace::scene::bsdf::hair::{Absorption, Hair};
    let probe = bsdf_probe();
    let white = Absorption::SigmaA {
        sigma_a: Vec3::ZERO,
        scale: 1.0,
    };
    let cases = [
        ("hair defaults", Hair::default(), dir(45.0, 0.0)),
        ("hair defaults", Hair::default(), dir(120.0, 70.0)),
        (
            "hair sharp",
            Hair {
                longitudinal_roughness: 0.12,
                azimuthal_roughness: 0.15,
                absorption: Absorption::Pigments {
                    eumelanin: 0.1,
                    pheomelanin: 0.3,
                },
                ..Hair::default()
            },
            dir(60.0, 20.0),
        ),
        (
            "hair rough, tilted",
            Hair {
                longitudinal_roughness: 0.8,
                azimuthal_roughness: 0.9,
                scale_tilt: -6.0,
                eta: 1.33,
                ..Hair::default()
            },
            dir(30.0, 200.0),
        ),
        (
            "hair white",
            Hair {
                absorption: white,
                ..Hair::default()
            },
            dir(80.0, 100.0),
        ),
        (
            "hair sigma_a",
            Hair {
                absorption: Absorption::SigmaA {
                    sigma_a: Vec3::new(0.2, 0.25, 0.7),
                    scale: 2.0,
                },
                longitudinal_roughness: 0.4,
                azimuthal_roughness: 0.25,
                scale_tilt: 5.0,
                ..Hair::default()
            },
            dir(10.0, 300.0),
        ),
    ];
    for (name, h, wo) in cases {
        bsdf_case(&probe, name, &Bsdf::Hair(h), wo, Axis::Normal, 14);
    }
    // Samples of a fiber whose scales tilt 4° against the pdf of one tilting 2°: the
    // R and TRT cones move by 4° and 12°.
    let wo = dir(50.0, 30.0);
    let right = BsdfRecord::from(&Bsdf::Hair(Hair::default()));
    let tilted = BsdfRecord::from(&Bsdf::Hair(Hair {
        scale_tilt: 4.0,
        ..Hair::default()
    }));
    let (own, _) = test_bsdf(&probe, &right, wo, Axis::Normal, N, 15).expect("bsdf kernel");
    let (other, _) = test_bsdf(&probe, &tilted, wo, Axis::Normal, N, 15).expect("bsdf kernel");
    assert_outcome("hair tilt 2°", &own);
    let wrong = wavetrace::warptest::chi2(&other.observed, &own.expected);
    assert!(
        wrong.p_value < 1e-12,
        "hair: samples of a 4° tilt passed against the 2° pdf: {wrong:?}"
    );
}
