//! White furnace tests: the directional albedo a(wo) = ∫ f |cos θi| dωi, estimated as
//! the mean of bsdf_sample's weights (importance sampling), for white versions of every
//! BSDF and many wo. No model may create energy (a <= 1 + 4σ); lossless smooth models
//! keep all of it (a = 1); microfacet models lose what single scattering cannot return
//! (light that would scatter again between microfacets): their albedos must equal an
//! independent f64 quadrature of the published models (tests/common/albedo.rs).
//!
//! Radiance transport scales refracted radiance by 1/η_it² (dielectrics); the test
//! multiplies refracted weights by η_it² to count energy (Veach 1997, sec. 5.2).

mod common;

use common::stats::{
    bsdf_probe, BsdfProbe, FLAG_DELTA, FLAG_NULL, FLAG_REFLECTION, FLAG_TRANSMISSION,
};
use glam::Vec3;
use wavetrace::gpu::layout::BsdfRecord;
use wavetrace::scene::bsdf::{
    thin_dielectric_reflectance, Bsdf, Conductor, Dielectric, Diffuse, Distribution,
    NoriMicrofacet, PPlastic, Plastic, RoughConductor, RoughDielectric, RoughPlastic,
    ThinDielectric,
};

use common::albedo::{self, Ndf, Quadrature};

const N: u32 = 100_000;

/// Mean and standard error of the energy weight over N samples.
fn albedo(probe: &BsdfProbe, bsdf: &Bsdf, wo: Vec3, eta: f32) -> (f64, f64) {
    let samples = probe
        .sample(&BsdfRecord::from(bsdf), wo, N, 21)
        .expect("bsdf kernel");
    let eta_it = if wo.z > 0.0 { eta } else { 1.0 / eta };
    let w: Vec<f64> = samples
        .iter()
        .map(|s| {
            let mut x = s.weight.x as f64;
            if s.flags & FLAG_TRANSMISSION != 0 {
                x *= (eta_it * eta_it) as f64;
            }
            x
        })
        .collect();
    let mean = w.iter().sum::<f64>() / w.len() as f64;
    let var = w.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (w.len() - 1) as f64;
    (mean, (var / w.len() as f64).sqrt())
}

fn wo_at(cos: f32, phi: f32) -> Vec3 {
    let s = (1.0 - cos * cos).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), cos)
}

/// cos θo of the tested directions: grazing to normal.
const COS: [f32; 6] = [0.05, 0.2, 0.4, 0.6, 0.8, 1.0];

/// Checks a <= 1 + 4σ for every wo and returns the albedos.
fn no_gain(
    probe: &BsdfProbe,
    name: &str,
    bsdf: &Bsdf,
    eta: f32,
    below: bool,
) -> Vec<(f32, f64, f64)> {
    let mut out = Vec::new();
    for (i, &c) in COS.iter().enumerate() {
        for sign in if below { vec![1.0, -1.0] } else { vec![1.0] } {
            let wo = wo_at(c, 0.7 * i as f32) * Vec3::new(1.0, 1.0, sign);
            let (a, se) = albedo(probe, bsdf, wo, eta);
            println!("{name}: cos θo = {:+.2}: albedo {a:.4} ± {se:.4}", wo.z);
            assert!(
                a <= 1.0 + 4.0 * se + 1e-5,
                "{name}, wo = {wo}: albedo {a} > 1 (± {se})"
            );
            out.push((wo.z, a, se));
        }
    }
    out
}

#[test]
fn lossless_smooth_models() {
    let probe = bsdf_probe();
    let white = Vec3::ONE;
    let cases = [
        (
            "diffuse white",
            Bsdf::Diffuse(Diffuse { reflectance: white }),
            1.0,
            false,
        ),
        (
            "twosided diffuse white",
            Bsdf::TwoSided(Box::new(Bsdf::Diffuse(Diffuse { reflectance: white }))),
            1.0,
            true,
        ),
        (
            "conductor none",
            Bsdf::Conductor(Conductor {
                eta: Vec3::ZERO,
                k: Vec3::ONE,
                specular_reflectance: white,
            }),
            1.0,
            false,
        ),
        (
            "dielectric 1.5",
            Bsdf::Dielectric(Dielectric {
                eta: 1.5,
                specular_reflectance: white,
                specular_transmittance: white,
            }),
            1.5,
            true,
        ),
        // A thin slab keeps all energy: R' reflected, 1 - R' passed undeflected (no
        // radiance scaling, so its energy eta is 1), from either side.
        (
            "thindielectric 1.5",
            Bsdf::ThinDielectric(ThinDielectric {
                eta: 1.5,
                specular_reflectance: white,
                specular_transmittance: white,
            }),
            1.0,
            true,
        ),
        (
            "dielectric 1/1.5",
            Bsdf::Dielectric(Dielectric {
                eta: 1.0 / 1.5,
                specular_reflectance: white,
                specular_transmittance: white,
            }),
            1.0 / 1.5,
            true,
        ),
        // White smooth plastic conserves energy exactly: the diffuse part returns
        // (1 - F_o)(1 - F_dr,ext) / (η² (1 - F_dr,int)) = 1 - F_o, since
        // 1 - F_dr,ext = η² (1 - F_dr,int) (reciprocity of the diffuse Fresnel terms).
        (
            "plastic white",
            Bsdf::Plastic(Plastic {
                diffuse_reflectance: white,
                specular_reflectance: white,
                eta: 1.49,
                nonlinear: false,
            }),
            1.0,
            false,
        ),
    ];
    for (name, bsdf, eta, below) in &cases {
        for (c, a, _) in no_gain(&probe, name, bsdf, *eta, *below) {
            // Deterministic weights of exactly 1 except plastic (MC noise; 100k samples
            // of weights within [0, 2] give σ < 3e-3) and F_dr's quadrature (< 1e-5).
            let tol = if name.starts_with("plastic") {
                1e-2
            } else {
                1e-4
            };
            assert!(
                (a - 1.0).abs() < tol,
                "{name}, cos θo = {c}: albedo {a} != 1"
            );
        }
    }
}

/// The GPU albedo `a ± se` (N samples) against the independent quadrature `q`: within
/// 5 standard errors of the N-sample mean (a false failure has probability 6e-7 per
/// direction, under 2e-4 over the ~250 directions of this file), plus the quadrature's
/// error bound, plus 2e-4 for the f32 weights. Returns whether it holds, and whether
/// the same check would reject the reference scaled by 0.95 (the power control: a 5%
/// energy error is seen).
fn agrees(a: f64, se: f64, q: Quadrature) -> (bool, bool) {
    let tol = 5.0 * se + q.error + 2e-4;
    ((a - q.value).abs() <= tol, (a - 0.95 * q.value).abs() > tol)
}

/// Each wo of `no_gain` against `reference(cos θo)`: asserts agreement and that a 5%
/// lower reference would be rejected.
fn assert_albedos(
    probe: &BsdfProbe,
    name: &str,
    bsdf: &Bsdf,
    eta: f32,
    below: bool,
    reference: impl Fn(f64) -> Quadrature,
) {
    for (c, a, se) in no_gain(probe, name, bsdf, eta, below) {
        let q = reference(c as f64);
        let (ok, power) = agrees(a, se, q);
        println!("  quadrature {:.4} ± {:.1e}", q.value, q.error);
        assert!(
            ok,
            "{name}, cos θo = {c}: albedo {a} ± {se}, quadrature {} ± {}",
            q.value, q.error
        );
        assert!(
            power,
            "{name}, cos θo = {c}: the check cannot see a 5% error (± {se})"
        );
    }
}

/// The quadrature itself against closed forms: a nearly smooth conductor and dielectric keep all energy, white smooth plastic keeps
/// all energy, and rough plastic at small α tends to smooth plastic.
#[test]
fn quadrature_reproduces_closed_forms() {
    for kind in [Ndf::Beckmann, Ndf::Ggx] {
        let c = albedo::rough_conductor_white(kind, 0.01, 0.7);
        assert!((c.value - 1.0).abs() < 2e-3, "{kind:?}: conductor {c:?}");
        for eta in [1.5, 1.0 / 1.5] {
            let d = albedo::rough_dielectric_white(kind, 0.01, eta, 0.7);
            assert!(
                (d.value - 1.0).abs() < 2e-3,
                "{kind:?} η = {eta}: dielectric {d:?}"
            );
        }
        let rp = albedo::rough_plastic(kind, 0.01, 0.5, 1.5, false, 0.7).total();
        let p = albedo::plastic(0.5, 1.5, false, 0.7);
        assert!(
            (rp.value - p.value).abs() < 5e-3,
            "{kind:?}: rough {rp:?}, smooth {p:?}"
        );
    }
    for mu in [0.05, 0.5, 1.0] {
        let p = albedo::plastic(1.0, 1.49, false, mu);
        assert!(
            (p.value - 1.0).abs() < 1e-6 + p.error,
            "plastic, μ = {mu}: {p:?}"
        );
    }
}

/// Single-scattering microfacet models (separable Smith G, as Mitsuba) lose light that
/// would bounce between microfacets; the GPU's albedos must equal the quadrature of the
/// published models (tests/common/albedo.rs), from both sides for dielectrics.
#[test]
fn microfacet_albedos_match_quadrature() {
    let probe = bsdf_probe();
    let white = Vec3::ONE;
    for (distribution, kind) in [
        (Distribution::Beckmann, Ndf::Beckmann),
        (Distribution::Ggx, Ndf::Ggx),
    ] {
        for alpha in [0.05f32, 0.3, 0.8] {
            let a = alpha as f64;
            let b = Bsdf::RoughConductor(RoughConductor {
                distribution,
                alpha_u: alpha,
                alpha_v: alpha,
                eta: Vec3::ZERO,
                k: Vec3::ONE,
                specular_reflectance: white,
            });
            let name = format!("roughconductor none {distribution:?} α = {alpha}");
            assert_albedos(&probe, &name, &b, 1.0, false, |mu| {
                albedo::rough_conductor_white(kind, a, mu)
            });
            for eta in [1.5f32, 1.0 / 1.5] {
                let name = format!("roughdielectric {distribution:?} α = {alpha} η = {eta:.3}");
                let b = Bsdf::RoughDielectric(RoughDielectric {
                    distribution,
                    alpha_u: alpha,
                    alpha_v: alpha,
                    eta,
                    specular_reflectance: white,
                    specular_transmittance: white,
                });
                // From below the interface is seen with the inverse index.
                assert_albedos(&probe, &name, &b, eta, true, |mu| {
                    let e = if mu > 0.0 {
                        eta as f64
                    } else {
                        1.0 / eta as f64
                    };
                    albedo::rough_dielectric_white(kind, a, e, mu.abs())
                });
            }
        }
    }
    for alpha in [0.1f32, 0.5] {
        // Nori's microfacet with kd = 0.5 (ks = 0.5).
        let eta = 1.5046 / 1.000277;
        let b = Bsdf::NoriMicrofacet(NoriMicrofacet {
            alpha,
            eta,
            kd: Vec3::splat(0.5),
        });
        assert_albedos(
            &probe,
            &format!("nori microfacet α = {alpha}"),
            &b,
            1.0,
            false,
            |mu| albedo::nori_microfacet(alpha as f64, 0.5, eta as f64, mu),
        );
    }
}

/// Smooth plastic with a grey base, linear and nonlinear, against the quadrature.
#[test]
fn plastic_albedo_matches_quadrature() {
    let probe = bsdf_probe();
    for nonlinear in [false, true] {
        let b = Bsdf::Plastic(Plastic {
            diffuse_reflectance: Vec3::splat(0.5),
            specular_reflectance: Vec3::ONE,
            eta: 1.49,
            nonlinear,
        });
        let name = format!("plastic 0.5 nonlinear = {nonlinear}");
        assert_albedos(&probe, &name, &b, 1.0, false, |mu| {
            albedo::plastic(0.5, 1.49, nonlinear, mu)
        });
    }
}

/// Mitsuba's `pplastic`, white and grey bases, both distributions, α up to 1, against
/// the quadrature of its model (`albedo::pplastic`): it never gains energy, and loses
/// what its ad-hoc sum drops (no internal scattering between the two refractions).
#[test]
fn pplastic_albedo_matches_quadrature() {
    let probe = bsdf_probe();
    for (distribution, kind) in [
        (Distribution::Beckmann, Ndf::Beckmann),
        (Distribution::Ggx, Ndf::Ggx),
    ] {
        for (alpha, rho) in [(0.05f32, 1.0f32), (0.3, 0.5), (1.0, 1.0)] {
            let b = Bsdf::PPlastic(PPlastic {
                distribution,
                alpha_u: alpha,
                alpha_v: alpha,
                diffuse_reflectance: Vec3::splat(rho),
                specular_reflectance: Vec3::ONE,
                eta: 1.49,
            });
            let name = format!("pplastic ρ = {rho} {distribution:?} α = {alpha}");
            assert_albedos(&probe, &name, &b, 1.0, false, |mu| {
                albedo::pplastic(kind, alpha as f64, rho as f64, 1.49, mu)
            });
        }
    }
}

/// Mitsuba 3.9.1's own roughplastic albedos (pip `mitsuba`, llvm_ad_rgb, white base,
/// int_ior 1.49): (distribution, α, [albedo at cos θo = 0.05, 0.5, 1.0]), each the mean
/// weight of 2^20 `sample` calls (weights in [0, 1.5]: standard error < 1e-3), measured
/// by python3 with mi.load_dict({'type': 'roughplastic', 'distribution': ..., 'alpha':
/// ..., 'int_ior': 1.49, 'ext_ior': 1.0, 'diffuse_reflectance': 1}).
const MITSUBA_ROUGH_PLASTIC: [(Ndf, f64, [f64; 3]); 4] = [
    (Ndf::Beckmann, 0.3, [0.8736, 0.8611, 0.8750]),
    (Ndf::Beckmann, 1.0, [0.4137, 0.4892, 0.5117]),
    (Ndf::Ggx, 0.3, [0.6160, 0.6732, 0.6945]),
    (Ndf::Ggx, 1.0, [0.1591, 0.2626, 0.3401]),
];

/// Rough plastic, white base, α up to 1, against the quadrature of Mitsuba's model
/// (`rough_plastic_quadrature_matches_mitsuba` shows the reference is Mitsuba's model)
/// and, where measured, against Mitsuba's own albedo.
///
/// The GPU reproduces Mitsuba's tables (its 32² Gauss-Legendre visible-normal
/// integrals, 64 tabulated μ, R_int as a 64-point mean), whose discretisation the exact
/// quadrature does not have: up to 1.4% at α = 0.05 (R_int 1.5% low, amplified by
/// 1/(1 - R_int) for a white base). So the quadrature is met within that 2% on top of
/// the noise (a 5% error is still told apart), and Mitsuba's own numbers within their
/// and our noise. Before issue 39's fix the GPU was up to 49% too bright (GGX α = 1:
/// its coating transmittance was 1 - R, giving back what Smith's shadowing loses).
#[test]
fn rough_plastic_albedo_matches_quadrature() {
    let probe = bsdf_probe();
    for (distribution, kind) in [
        (Distribution::Beckmann, Ndf::Beckmann),
        (Distribution::Ggx, Ndf::Ggx),
    ] {
        for alpha in [0.05f32, 0.3, 0.6, 1.0] {
            let name = format!("roughplastic white {distribution:?} α = {alpha}");
            let b = Bsdf::RoughPlastic(RoughPlastic {
                distribution,
                alpha,
                diffuse_reflectance: Vec3::ONE,
                specular_reflectance: Vec3::ONE,
                eta: 1.49,
                nonlinear: false,
            });
            let mitsuba = MITSUBA_ROUGH_PLASTIC
                .iter()
                .find(|(k, a, _)| *k == kind && *a == alpha as f64);
            for (c, a, se) in no_gain(&probe, &name, &b, 1.0, false) {
                let q =
                    albedo::rough_plastic(kind, alpha as f64, 1.0, 1.49, false, c as f64).total();
                let tol = 5.0 * se + q.error + 2e-4 + 0.02 * q.value;
                println!(
                    "  quadrature {:.4} ± {:.1e}: GPU / quadrature {:.4}",
                    q.value,
                    q.error,
                    a / q.value
                );
                assert!(
                    (a - q.value).abs() <= tol,
                    "{name}, cos θo = {c}: albedo {a} ± {se}, quadrature {} ± {}",
                    q.value,
                    q.error
                );
                assert!(
                    (a - 0.95 * q.value).abs() > tol,
                    "{name}, cos θo = {c}: the check cannot see a 5% error"
                );
                let at = [0.05f32, 0.5, 1.0]
                    .iter()
                    .position(|&x| (x - c).abs() < 1e-4);
                if let (Some((_, _, m)), Some(k)) = (mitsuba, at) {
                    println!("  Mitsuba {:.4}: GPU / Mitsuba {:.4}", m[k], a / m[k]);
                    assert!(
                        (a - m[k]).abs() <= 5.0 * se + 5e-3,
                        "{name}, cos θo = {c}: albedo {a} ± {se}, Mitsuba {}",
                        m[k]
                    );
                }
            }
        }
    }
}

/// The rough-plastic reference is Mitsuba's model: Mitsuba 3.9.1's own roughplastic
/// ([`MITSUBA_ROUGH_PLASTIC`]) against the quadrature. Within 2%: Mitsuba integrates the coating's T(μ) with 32²
/// Gauss-Legendre visible normals, tabulates it at 64 μ, and takes R_int as a 64-point
/// mean; those errors are amplified by 1/(1 - R_int) ≈ 2.5 for a white base (at α =
/// 0.05 they reach 2%, so that α is left out).
#[test]
fn rough_plastic_quadrature_matches_mitsuba() {
    for (kind, alpha, want) in MITSUBA_ROUGH_PLASTIC {
        for (mu, m) in [0.05, 0.5, 1.0].into_iter().zip(want) {
            let q = albedo::rough_plastic(kind, alpha, 1.0, 1.49, false, mu).total();
            println!(
                "{kind:?} α = {alpha} μ = {mu}: quadrature {:.4}, Mitsuba {m:.4}",
                q.value
            );
            assert!(
                (q.value - m).abs() < 0.02 * m + q.error,
                "{kind:?} α = {alpha} μ = {mu}: quadrature {}, Mitsuba {m}",
                q.value
            );
            // The power control: a 5% different model is told apart.
            assert!((0.95 * q.value - m).abs() > 0.02 * m + q.error);
        }
    }
}

/// The thin dielectric picks its lobes as Mitsuba's thindielectric.cpp: reflection
/// (the mirror direction, flags reflection | delta) with probability R' = 2R / (1 + R)
/// of the Fresnel reflectance R at |cos θo| (from either side alike), else straight
/// through (wi = -wo, flags transmission | null | delta), each with weight 1 for white
/// (f / P: the lobe's share over the probability of picking it); a tinted slab weighs
/// its reflection by specular_reflectance and its transmission by
/// specular_transmittance. The share of reflections must match R' within 5 binomial
/// standard errors (a false failure has probability < 1e-6 per direction).
#[test]
fn thin_dielectric_lobes() {
    let probe = bsdf_probe();
    let (refl, trans) = (Vec3::new(0.9, 0.5, 0.2), Vec3::new(0.3, 0.6, 1.0));
    for eta in [1.5f32, 1.333] {
        let b = Bsdf::ThinDielectric(ThinDielectric {
            eta,
            specular_reflectance: refl,
            specular_transmittance: trans,
        });
        for (i, &c) in COS.iter().enumerate() {
            for sign in [1.0f32, -1.0] {
                let wo = wo_at(c, 0.7 * i as f32) * Vec3::new(1.0, 1.0, sign);
                let samples = probe
                    .sample(&BsdfRecord::from(&b), wo, N, 5)
                    .expect("bsdf kernel");
                let want = thin_dielectric_reflectance(wo.z as f64, eta as f64);
                let mut reflected = 0usize;
                for s in &samples {
                    if s.flags & FLAG_REFLECTION != 0 {
                        reflected += 1;
                        assert_eq!(s.flags, FLAG_REFLECTION | FLAG_DELTA);
                        assert!((s.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-6);
                        assert!((s.weight - refl).length() < 1e-6, "{}", s.weight);
                    } else {
                        assert_eq!(s.flags, FLAG_TRANSMISSION | FLAG_NULL | FLAG_DELTA);
                        assert!((s.wi + wo).length() < 1e-6);
                        assert!((s.weight - trans).length() < 1e-6, "{}", s.weight);
                    }
                    assert_eq!(s.pdf, 0.0);
                }
                let share = reflected as f64 / N as f64;
                let se = (want * (1.0 - want) / N as f64).sqrt().max(1e-6);
                println!(
                    "thindielectric η = {eta}, cos θo = {:+.2}: R' = {want:.4}, sampled {share:.4}",
                    wo.z
                );
                assert!(
                    (share - want).abs() < 5.0 * se,
                    "η = {eta}, cos θo = {}: reflected {share}, R' = {want}",
                    wo.z
                );
            }
        }
    }
}

/// Mitsuba's `principled` and `principledthin` (which are not energy conserving:
/// Disney's lobes are summed): the directional albedo, per RGB channel, against the
/// mean of Mitsuba 3.9.1's own `sample` weights (tests/data/principled_albedo.json,
/// `python3 tools/mitsuba_principled_albedo.py`, 200,000 samples per direction), from
/// above and below, within 4.5 standard errors of the difference (90 comparisons:
/// a false alarm about once in 1700 runs). A white metal also keeps a <= 1.
#[test]
fn principled_albedo_matches_mitsuba() {
    let text = std::fs::read_to_string(common::repo("tests/data/principled_albedo.json"))
        .expect("tests/data/principled_albedo.json (python3 tools/mitsuba_principled_albedo.py)");
    let data: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let probe = bsdf_probe();
    let num = |v: &serde_json::Value| v.as_f64().expect("a number");
    for (i, case) in data["cases"].as_array().expect("cases").iter().enumerate() {
        let bsdf = common::bsdf_from_mitsuba_dict(&case["mitsuba"], &format!("furnace{i}"));
        let rec = BsdfRecord::from(&bsdf);
        for a in case["albedos"].as_array().expect("albedos") {
            let wo: Vec<f32> = a["wo"]
                .as_array()
                .expect("wo")
                .iter()
                .map(|x| num(x) as f32)
                .collect();
            let wo = Vec3::new(wo[0], wo[1], wo[2]).normalize();
            let samples = probe.sample(&rec, wo, N, 23).expect("bsdf kernel");
            for k in 0..3 {
                let w: Vec<f64> = samples.iter().map(|s| s.weight[k] as f64).collect();
                let mean = w.iter().sum::<f64>() / w.len() as f64;
                let var =
                    w.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (w.len() - 1) as f64;
                let se = (var / w.len() as f64).sqrt();
                let (want, want_se) = (num(&a["albedo"][k]), num(&a["se"][k]));
                let sigma = (se * se + want_se * want_se).sqrt();
                println!(
                    "{}, wo = {wo:.2}, channel {k}: albedo {mean:.4} ± {se:.4}, Mitsuba {want:.4} ± {want_se:.4}",
                    case["mitsuba"]
                );
                assert!(
                    (mean - want).abs() <= 4.5 * sigma + 1e-6,
                    "{}, wo = {wo}, channel {k}: albedo {mean} ± {se}, Mitsuba {want} ± {want_se}",
                    case["mitsuba"]
                );
                if case["mitsuba"]["metallic"].as_f64() == Some(1.0) {
                    assert!(mean <= 1.0 + 4.0 * se, "white metal gains energy: {mean}");
                }
            }
        }
    }
}

/// Mitsuba's `hair` (Chiang et al. 2016) keeps all energy without absorption: its
/// attenuations sum to 1 (f + (1 - f)² (1 + f + f² / (1 - f)) = 1) and each lobe is a
/// normalized density. Checked by an independent quadrature of bsdf_eval over the
/// sphere (a 64 x 48 grid around the fiber, 6 x 6 points a cell) for white fibers of
/// several roughnesses, tilts and indices, viewers along and across the fiber; and the
/// mean sample weight of an absorbing fiber equals its quadrature.
///
/// Mitsuba's d'Eon lobe sums I0 by 11 terms of its series (and uses an asymptotic
/// form above 12), which loses a little where κ cos θi cos θo nears 12: 0.146% for
/// the default fiber seen across (a double-precision quadrature of Mitsuba's formulas
/// gives the same 0.99855), so the test allows 0.5% below 1 and 0.2% above (the
/// quadrature's own error). Sampling draws the exact lobes, so its mean weight may
/// exceed the quadrature of the truncated pdf by as much (0.2% seen; 0.5% allowed).
#[test]
fn hair_white_furnace() {
    use wavetrace::scene::bsdf::hair::{Absorption, Hair};
    use wavetrace::warptest::SphereGrid;
    let probe = bsdf_probe();
    let (dirs, w) = SphereGrid::new(Vec3::Y, 64, 48).quadrature(6);
    let integral = |rec: &BsdfRecord, wo: Vec3| -> Vec3 {
        let e = probe.eval(rec, wo, &dirs).expect("bsdf kernel");
        e.iter()
            .zip(&w)
            .fold(glam::DVec3::ZERO, |acc, (v, w)| acc + v.0.as_dvec3() * *w)
            .as_vec3()
    };
    let white = Absorption::SigmaA {
        sigma_a: Vec3::ZERO,
        scale: 1.0,
    };
    let fibers = [
        Hair {
            absorption: white,
            ..Hair::default()
        },
        Hair {
            absorption: white,
            longitudinal_roughness: 0.15,
            azimuthal_roughness: 0.2,
            ..Hair::default()
        },
        Hair {
            absorption: white,
            longitudinal_roughness: 0.8,
            azimuthal_roughness: 0.9,
            scale_tilt: -5.0,
            eta: 1.33,
        },
    ];
    // Viewers at fiber angles θ (sin θ = wo.y) of -70..80 degrees, around the fiber.
    let viewers: Vec<Vec3> = [
        (-70.0f32, 20.0f32),
        (-20.0, 250.0),
        (0.0, 90.0),
        (35.0, 170.0),
        (80.0, 300.0),
    ]
    .iter()
    .map(|&(t, p)| {
        let (t, p) = (t.to_radians(), p.to_radians());
        Vec3::new(t.cos() * p.cos(), t.sin(), t.cos() * p.sin())
    })
    .collect();
    for h in fibers {
        let rec = BsdfRecord::from(&Bsdf::Hair(h));
        for &wo in &viewers {
            let a = integral(&rec, wo);
            println!(
                "hair β = ({}, {}), α = {}, η = {}: wo = {wo:.2}: ∫ f cos = {a:.5}",
                h.longitudinal_roughness, h.azimuthal_roughness, h.scale_tilt, h.eta
            );
            assert!(
                a.max_element() < 1.002 && a.min_element() > 0.995,
                "white hair {h:?}, wo = {wo}: ∫ f cos = {a}"
            );
        }
    }
    // An absorbing fiber: sampling's mean weight is the same integral.
    let brown = BsdfRecord::from(&Bsdf::Hair(Hair::default()));
    for &wo in &viewers[1..4] {
        let q = integral(&brown, wo);
        let samples = probe.sample(&brown, wo, N, 22).expect("bsdf kernel");
        for k in 0..3 {
            let x: Vec<f64> = samples.iter().map(|s| s.weight[k] as f64).collect();
            let mean = x.iter().sum::<f64>() / x.len() as f64;
            let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (x.len() - 1) as f64;
            let se = (var / x.len() as f64).sqrt();
            println!("hair default, wo = {wo:.2}, channel {k}: sampled {mean:.5} ± {se:.5}, quadrature {:.5}", q[k]);
            assert!(
                (mean - q[k] as f64).abs() < 4.0 * se + 0.005 * q[k] as f64,
                "hair default, wo = {wo}, channel {k}: sampled {mean} ± {se}, quadrature {}",
                q[k]
            );
        }
    }
}
