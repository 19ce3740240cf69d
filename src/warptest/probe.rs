//! GPU runners for the sampling kernels under test: `shaders/tests/warp.comp` (the
//! warps of warp.glsl and the microfacet normals of microfacet.glsl),
//! `shaders/tests/sample_bsdf.comp` (bsdf_sample, bsdf_eval, bsdf_pdf of one record)
//! and `shaders/tests/phase.comp` (Henyey-Greenstein). Each draws samples with the
//! kernel's own random numbers (a hash of the index and a seed) and evaluates the
//! pdf at given points, in GLSL as the renderer runs it.

use glam::Vec3;

use crate::gpu::layout::BsdfRecord;
use crate::gpu::{
    shaders, BindingLayout, Buffer, CommandList, DescriptorSet, Device, Kernel, Location, Result,
};

/// Dispatches `kernel` over `count` items in workgroups of 64 (2D past 65535 groups),
/// with `inputs` (never empty: a dummy texel stands in) and an output of `outputs`
/// vec4s; returns the output.
fn dispatch(
    device: &Device,
    layout: &BindingLayout,
    kernel: &Kernel,
    inputs: &[&[[f32; 4]]],
    outputs: usize,
    push: &[u8],
    count: u32,
) -> Result<Vec<[f32; 4]>> {
    let dummy = [[0f32; 4]];
    let mut buffers = Vec::new();
    for data in inputs {
        let data = if data.is_empty() { &dummy[..] } else { data };
        buffers.push(Buffer::from_slice(device, "warptest input", data)?);
    }
    let out = Buffer::new(
        device,
        "warptest output",
        (outputs as u64 * 16).max(16),
        Location::Gpu,
    )?;
    let mut refs: Vec<&Buffer> = buffers.iter().collect();
    refs.push(&out);
    let set = DescriptorSet::new(layout, 0, &refs)?;
    let mut cmd = CommandList::new(device)?;
    let groups = count.div_ceil(64).max(1);
    cmd.dispatch(
        kernel,
        &[&set],
        push,
        [groups.min(65535), groups.div_ceil(65535), 1],
    );
    cmd.barrier();
    cmd.submit_and_wait()?;
    let mut v: Vec<[f32; 4]> = out.read(device)?;
    v.truncate(outputs);
    Ok(v)
}

/// GPU runner for `shaders/tests/sample_bsdf.comp`.
pub struct BsdfProbe {
    pub device: Device,
    layout: BindingLayout,
    kernel: Kernel,
    /// The table words of models that read tables (`measured`), set by
    /// [`BsdfProbe::set_tables`]; four a vec4.
    tables: Vec<[f32; 4]>,
}

/// One `bsdf_sample` result with eval and pdf at its direction.
#[derive(Debug, Clone, Copy)]
pub struct Sampled {
    pub wi: Vec3,
    pub pdf: f32,
    pub weight: Vec3,
    pub flags: u32,
    pub eval: Vec3,
    pub pdf_eval: f32,
}

/// [`Sampled::flags`], as `BSDF_FLAG_*` in bsdf.glsl.
pub const FLAG_REFLECTION: u32 = 1;
pub const FLAG_TRANSMISSION: u32 = 2;
pub const FLAG_DELTA: u32 = 4;
/// Straight through without bending (thin dielectric).
pub const FLAG_NULL: u32 = 8;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct BsdfPush {
    wo: [f32; 4],
    mode: u32,
    count: u32,
    seed: u32,
    /// Where the table words start in the direction buffer, in vec4s.
    tables: u32,
}

impl BsdfPush {
    fn new(wo: Vec3, mode: u32, count: u32, seed: u32) -> BsdfPush {
        BsdfPush {
            wo: [wo.x, wo.y, wo.z, 0.0],
            mode,
            count,
            seed,
            tables: 0,
        }
    }
}

impl BsdfProbe {
    pub fn new(device: &Device) -> Result<BsdfProbe> {
        let layout = BindingLayout::new(device, &[3], 32)?;
        let kernel = Kernel::new(
            device,
            "sample_bsdf",
            shaders::TESTS_SAMPLE_BSDF,
            &layout,
            &[],
        )?;
        Ok(BsdfProbe {
            device: device.clone(),
            layout,
            kernel,
            tables: Vec::new(),
        })
    }

    /// Gives the records evaluated from now on the table words `words`
    /// (`scene::bsdf::measured::record_with_tables`).
    pub fn set_tables(&mut self, words: &[f32]) {
        self.tables = words
            .chunks(4)
            .map(|c| std::array::from_fn(|i| c.get(i).copied().unwrap_or(0.0)))
            .collect();
    }

    fn run(
        &self,
        recs: &[BsdfRecord],
        mut push: BsdfPush,
        dirs: &[[f32; 4]],
        outputs: usize,
    ) -> Result<Vec<[f32; 4]>> {
        let recs: &[[f32; 4]] = bytemuck::cast_slice(recs);
        let with_tables;
        let dirs = if self.tables.is_empty() {
            dirs
        } else {
            push.tables = dirs.len() as u32;
            with_tables = [dirs, &self.tables].concat();
            &with_tables
        };
        dispatch(
            &self.device,
            &self.layout,
            &self.kernel,
            &[recs, dirs],
            outputs,
            bytemuck::bytes_of(&push),
            push.count,
        )
    }

    /// `count` samples of `bsdf_sample(rec, wo)` (u from a hash of the index and seed).
    pub fn sample(
        &self,
        rec: &BsdfRecord,
        wo: Vec3,
        count: u32,
        seed: u32,
    ) -> Result<Vec<Sampled>> {
        self.sample_records(std::slice::from_ref(rec), wo, count, seed)
    }

    /// [`BsdfProbe::sample`] of the records of one BSDF (`composite::records`): a
    /// model's one record, or a blend node with its two models (the mixture of
    /// `shaders/bsdf/mixture.glsl`).
    pub fn sample_records(
        &self,
        recs: &[BsdfRecord],
        wo: Vec3,
        count: u32,
        seed: u32,
    ) -> Result<Vec<Sampled>> {
        let raw = self.run(
            recs,
            BsdfPush::new(wo, 0, count, seed),
            &[],
            3 * count as usize,
        )?;
        Ok(raw
            .chunks_exact(3)
            .map(|c| Sampled {
                wi: Vec3::new(c[0][0], c[0][1], c[0][2]),
                pdf: c[0][3],
                weight: Vec3::new(c[1][0], c[1][1], c[1][2]),
                flags: c[1][3].to_bits(),
                eval: Vec3::new(c[2][0], c[2][1], c[2][2]),
                pdf_eval: c[2][3],
            })
            .collect())
    }

    /// (bsdf_eval, bsdf_pdf) at each direction.
    pub fn eval(&self, rec: &BsdfRecord, wo: Vec3, dirs: &[[f32; 4]]) -> Result<Vec<(Vec3, f32)>> {
        self.eval_records(std::slice::from_ref(rec), wo, dirs)
    }

    /// [`BsdfProbe::eval`] of the records of one BSDF, as [`BsdfProbe::sample_records`].
    pub fn eval_records(
        &self,
        recs: &[BsdfRecord],
        wo: Vec3,
        dirs: &[[f32; 4]],
    ) -> Result<Vec<(Vec3, f32)>> {
        let push = BsdfPush::new(wo, 1, dirs.len() as u32, 0);
        let raw = self.run(recs, push, dirs, dirs.len())?;
        Ok(raw
            .iter()
            .map(|v| (Vec3::new(v[0], v[1], v[2]), v[3]))
            .collect())
    }
}

/// Which warp of `shaders/tests/warp.comp` to run, with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Warp {
    /// Concentric map of the square to the unit disk; pdf per unit area.
    Disk,
    UniformHemisphere,
    CosineHemisphere,
    UniformSphere,
    /// Uniform directions in the cap cos θ >= cos_max.
    Cap {
        cos_max: f32,
    },
    /// Uniform barycentrics (b0, b1).
    Triangle,
    /// Microfacet normals: `distribution` 0 Beckmann (D cos θm), 1 GGX (visible
    /// normals for `wo`), anisotropic roughness.
    Microfacet {
        distribution: u32,
        alpha_u: f32,
        alpha_v: f32,
        wo: Vec3,
    },
    /// A deliberately wrong pair for testing the test: cosine-weighted samples
    /// against the uniform hemisphere's pdf. It must fail.
    MismatchedCosine,
    /// The thin-lens camera's aperture sampling on the unit disk
    /// (shaders/sensor/thinlens.glsl); pdf per unit area.
    ThinLensAperture,
    /// A projector's photon directions for uniform image points, in its frame
    /// (shaders/emitter/projector.glsl): the image plane z = 1 spans ±`tan_x`, ±`tan_y`.
    Projector {
        tan_x: f32,
        tan_y: f32,
    },
}

impl Warp {
    /// Whether the warp's samples are directions (else points in the plane).
    pub fn spherical(&self) -> bool {
        !matches!(self, Warp::Disk | Warp::Triangle | Warp::ThinLensAperture)
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct WarpPush {
    param: [f32; 4],
    mf: [f32; 4],
    warp: u32,
    mode: u32,
    count: u32,
    seed: u32,
}

impl Warp {
    fn push(&self, mode: u32, count: u32, seed: u32) -> WarpPush {
        let (warp, param, mf) = match *self {
            Warp::Disk => (0, [0.0; 4], [0.0; 4]),
            Warp::UniformHemisphere => (1, [0.0; 4], [0.0; 4]),
            Warp::CosineHemisphere => (2, [0.0; 4], [0.0; 4]),
            Warp::UniformSphere => (3, [0.0; 4], [0.0; 4]),
            Warp::Cap { cos_max } => (4, [cos_max, 0.0, 0.0, 0.0], [0.0; 4]),
            Warp::Triangle => (5, [0.0; 4], [0.0; 4]),
            Warp::Microfacet {
                distribution,
                alpha_u,
                alpha_v,
                wo,
            } => (
                6,
                [wo.x, wo.y, wo.z, 0.0],
                [distribution as f32, alpha_u, alpha_v, 0.0],
            ),
            Warp::MismatchedCosine => (7, [0.0; 4], [0.0; 4]),
            Warp::ThinLensAperture => (8, [0.0; 4], [0.0; 4]),
            Warp::Projector { tan_x, tan_y } => (9, [tan_x, tan_y, 0.0, 0.0], [0.0; 4]),
        };
        WarpPush {
            param,
            mf,
            warp,
            mode,
            count,
            seed,
        }
    }
}

/// GPU runner for `shaders/tests/warp.comp`.
pub struct WarpProbe {
    pub device: Device,
    layout: BindingLayout,
    kernel: Kernel,
}

impl WarpProbe {
    pub fn new(device: &Device) -> Result<WarpProbe> {
        let layout = BindingLayout::new(device, &[2], 48)?;
        let kernel = Kernel::new(device, "warp", shaders::TESTS_WARP, &layout, &[])?;
        Ok(WarpProbe {
            device: device.clone(),
            layout,
            kernel,
        })
    }

    fn run(&self, push: WarpPush, points: &[[f32; 4]]) -> Result<Vec<[f32; 4]>> {
        dispatch(
            &self.device,
            &self.layout,
            &self.kernel,
            &[points],
            push.count as usize,
            bytemuck::bytes_of(&push),
            push.count,
        )
    }

    /// `count` warped points (xyz) with the pdf the kernel computes at each.
    pub fn sample(&self, warp: Warp, count: u32, seed: u32) -> Result<Vec<[f32; 4]>> {
        self.run(warp.push(0, count, seed), &[])
    }

    /// The warp's pdf at each point.
    pub fn pdf(&self, warp: Warp, points: &[[f32; 4]]) -> Result<Vec<f64>> {
        Ok(self
            .run(warp.push(1, points.len() as u32, 0), points)?
            .iter()
            .map(|v| v[0] as f64)
            .collect())
    }
}

/// GPU runner for `shaders/tests/phase.comp` (Henyey-Greenstein with asymmetry `g`;
/// 0 is isotropic).
pub struct PhaseProbe {
    pub device: Device,
    layout: BindingLayout,
    kernel: Kernel,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct PhasePush {
    wo: [f32; 4],
    g: f32,
    mode: u32,
    count: u32,
    seed: u32,
}

/// One `phase_sample` result: the direction, the pdf sampling returned, and
/// phase_eval and phase_pdf at that direction.
#[derive(Debug, Clone, Copy)]
pub struct PhaseSampled {
    pub wi: Vec3,
    pub pdf: f32,
    pub eval: f32,
    pub pdf_eval: f32,
}

impl PhaseProbe {
    pub fn new(device: &Device) -> Result<PhaseProbe> {
        let layout = BindingLayout::new(device, &[2], 32)?;
        let kernel = Kernel::new(device, "phase", shaders::TESTS_PHASE, &layout, &[])?;
        Ok(PhaseProbe {
            device: device.clone(),
            layout,
            kernel,
        })
    }

    fn run(&self, push: PhasePush, dirs: &[[f32; 4]], per_item: usize) -> Result<Vec<[f32; 4]>> {
        dispatch(
            &self.device,
            &self.layout,
            &self.kernel,
            &[dirs],
            push.count as usize * per_item,
            bytemuck::bytes_of(&push),
            push.count,
        )
    }

    /// `count` samples of phase_sample(g, wo).
    pub fn sample(&self, g: f32, wo: Vec3, count: u32, seed: u32) -> Result<Vec<PhaseSampled>> {
        let push = PhasePush {
            wo: [wo.x, wo.y, wo.z, 0.0],
            g,
            mode: 0,
            count,
            seed,
        };
        Ok(self
            .run(push, &[], 2)?
            .chunks(2)
            .map(|c| PhaseSampled {
                wi: Vec3::new(c[0][0], c[0][1], c[0][2]),
                pdf: c[0][3],
                eval: c[1][0],
                pdf_eval: c[1][1],
            })
            .collect())
    }

    /// phase_pdf at each direction.
    pub fn pdf(&self, g: f32, wo: Vec3, dirs: &[[f32; 4]]) -> Result<Vec<f64>> {
        let push = PhasePush {
            wo: [wo.x, wo.y, wo.z, 0.0],
            g,
            mode: 1,
            count: dirs.len() as u32,
            seed: 0,
        };
        Ok(self
            .run(push, dirs, 1)?
            .iter()
            .map(|v| v[0] as f64)
            .collect())
    }
}
