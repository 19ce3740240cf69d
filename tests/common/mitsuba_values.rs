//! Readers of the JSON that tools/mitsuba_*_values.py write (BSDF values Mitsuba 3
//! computed), shared by the tests that compare the GPU's eval and pdf with them, and
//! the comparison loop itself.

use glam::Vec3;
use serde_json::Value;
use wavetrace::gpu::layout::BsdfRecord;
use wavetrace::scene::bsdf::Distribution;
use wavetrace::warptest::BsdfProbe;

/// Half an f32 ulp at 1 (the unit roundoff, 2⁻²⁴).
pub const EPS: f64 = f32::EPSILON as f64 / 2.0;

/// A JSON array of three numbers.
pub fn v3(v: &Value) -> Vec3 {
    let a: Vec<f32> = v
        .as_array()
        .expect("a vector")
        .iter()
        .map(|x| x.as_f64().expect("a number") as f32)
        .collect();
    Vec3::new(a[0], a[1], a[2])
}

/// A JSON number.
pub fn num(v: &Value) -> f32 {
    v.as_f64().expect("a number") as f32
}

/// One (wo, wi) pair of a case and Mitsuba's eval (cosine-weighted, RGB) and pdf
/// (solid angle) there.
pub struct Pair {
    pub wo: Vec3,
    pub wi: Vec3,
    pub eval: Vec3,
    pub pdf: f64,
}

/// A case of a values file: its parameters (the JSON object: `mitsuba`, the
/// dictionary Mitsuba loaded, and whatever else the script wrote) and its pairs.
pub struct Case {
    pub params: Value,
    pub pairs: Vec<Pair>,
}

impl Case {
    /// The largest eval of the case (over pairs and channels).
    pub fn eval_scale(&self) -> f64 {
        self.pairs
            .iter()
            .map(|p| p.eval.max_element() as f64)
            .fold(0.0, f64::max)
    }

    /// The largest pdf of the case.
    pub fn pdf_scale(&self) -> f64 {
        self.pairs.iter().map(|p| p.pdf).fold(0.0, f64::max)
    }
}

/// The cases of `file` (relative to the repository), which `command` writes.
pub fn read_cases(file: &str, command: &str) -> Vec<Case> {
    let text = std::fs::read_to_string(super::repo(file))
        .unwrap_or_else(|e| panic!("{file} ({command}): {e}"));
    let data: Value = serde_json::from_str(&text).expect("JSON");
    data["cases"]
        .as_array()
        .expect("cases")
        .iter()
        .map(|case| Case {
            pairs: case["values"]
                .as_array()
                .expect("values")
                .iter()
                .map(|v| Pair {
                    wo: v3(&v["wo"]),
                    wi: v3(&v["wi"]),
                    eval: v3(&v["eval"]),
                    pdf: v["pdf"].as_f64().expect("pdf"),
                })
                .collect(),
            params: case.clone(),
        })
        .collect()
}

/// How far the GPU's value may be from Mitsuba's `w`: `rel |w| + abs`.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    pub rel: f64,
    pub abs: f64,
}

impl Tolerance {
    pub fn new(rel: f64, abs: f64) -> Self {
        Tolerance { rel, abs }
    }

    pub fn of(&self, w: f64) -> f64 {
        self.rel * w.abs() + self.abs
    }
}

/// What [`compare_eval_pdf`] found: the worst relative differences of eval and pdf
/// (over Mitsuba's values above the floors it was given) and every value outside its
/// tolerance.
pub struct Agreement {
    pub worst_eval: f64,
    pub worst_pdf: f64,
    pub failures: Vec<String>,
}

impl Agreement {
    /// Prints the worst relative differences of `case`, then
    /// [`Agreement::assert_agrees`].
    pub fn print_and_assert(&self, case: &str, pairs: usize) {
        println!(
            "{case}: {pairs} pairs; worst relative |GPU - Mitsuba|: eval {:.1e}, pdf {:.1e}",
            self.worst_eval, self.worst_pdf
        );
        self.assert_agrees(case, pairs);
    }

    /// Panics, naming `case` and the first failures, unless every value agreed.
    pub fn assert_agrees(&self, case: &str, pairs: usize) {
        assert!(
            self.failures.is_empty(),
            "{case}: {} of {pairs} pairs' values differ from Mitsuba's:\n{}",
            self.failures.len(),
            self.failures[..self.failures.len().min(20)].join("\n")
        );
    }
}

/// The GPU's bsdf_eval and bsdf_pdf of `rec` at each pair against Mitsuba's values:
/// `tolerance` gives each pair's (eval, pdf) tolerances; values of Mitsuba's at or
/// below `report_above` (eval, pdf) enter no worst relative difference.
pub fn compare_eval_pdf(
    probe: &BsdfProbe,
    rec: &BsdfRecord,
    pairs: &[Pair],
    report_above: [f64; 2],
    tolerance: impl Fn(&Pair) -> [Tolerance; 2],
) -> Agreement {
    let mut a = Agreement {
        worst_eval: 0.0,
        worst_pdf: 0.0,
        failures: Vec::new(),
    };
    for p in pairs {
        let (wo, wi) = (p.wo, p.wi);
        let got = probe
            .eval(rec, wo, &[[wi.x, wi.y, wi.z, 0.0]])
            .expect("bsdf kernel")[0];
        let [tol_eval, tol_pdf] = tolerance(p);
        for k in 0..3 {
            let (g, w) = (got.0[k] as f64, p.eval[k] as f64);
            if w.abs() > report_above[0] {
                a.worst_eval = a.worst_eval.max((g - w).abs() / w.abs());
            }
            let tol = tol_eval.of(w);
            let within = (g - w).abs() <= tol; // false for a NaN too
            if !within {
                a.failures.push(format!(
                    "wo {wo}, wi {wi}: eval[{k}] {g}, Mitsuba {w} (tolerance {tol:e})"
                ));
            }
        }
        let (g, w) = (got.1 as f64, p.pdf);
        if w > report_above[1] {
            a.worst_pdf = a.worst_pdf.max((g - w).abs() / w);
        }
        let tol = tol_pdf.of(w);
        let within = (g - w).abs() <= tol;
        if !within {
            a.failures.push(format!(
                "wo {wo}, wi {wi}: pdf {g}, Mitsuba {w} (tolerance {tol:e})"
            ));
        }
    }
    a
}

/// The exponent x = tan²θm / α² of Beckmann's D = exp(-x) / (π α_u α_v cos⁴θm) at the
/// half vector of (wo, wi) (anisotropic: (m_x / α_u)² + (m_y / α_v)², over m_z²); 0
/// for GGX, whose D is rational.
pub fn beckmann_exponent(
    distribution: Distribution,
    alpha_u: f32,
    alpha_v: f32,
    wo: Vec3,
    wi: Vec3,
) -> f64 {
    let m = (wo + wi).normalize();
    if distribution != Distribution::Beckmann || m.z <= 0.0 {
        return 0.0;
    }
    let (x, y, z) = (m.x as f64, m.y as f64, m.z as f64);
    let (au, av) = (alpha_u as f64, alpha_v as f64);
    ((x / au).powi(2) + (y / av).powi(2)) / (z * z)
}
