//! Chi-square tests of emitter sampling routines that read a whole scene (the shape an
//! emitter sits on, a mesh's triangle table): `wavetrace warptest directionalarea`.
//! The tests themselves (grids, expected counts, the verdict) are `warptest`'s; this
//! layer adds the scene's buffers, which `warptest` sits below.
//!
//! A directionalarea emitter's light rays (`shaders/emitter/directionalarea.glsl`, as
//! the photon and particle tracers draw them) start at points of its shape whose
//! density the rays' weight divides by, `emitter_directionalarea_pdf` (per unit area
//! in world space). The points are histogrammed in the shape's own chart (a mesh's or
//! a disk's local plane, a sphere's directions from its centre) and compared with that
//! density times the chart's area element, which the host knows from the placement:
//! a wrong area in the record, an alias table not by area or a warp that is not
//! uniform all fail. Each sample's direction must also be the shape's normal, its
//! weight radiance x area and its pdf 1 / area, with the area the host knows from the
//! placement (a sample that is not counts as off the domain, which fails the test).

use glam::{Affine3A, Mat3, Vec3};

use super::scene_buffers::{SceneBuffers, SceneRecords};
use super::scene_parts::scene_binding_kinds;
use super::{Error, Result};
use crate::accel::{prims_from_scene, Bvh, FlatPrims};
use crate::gpu::layout::Frame;
use crate::gpu::{
    shaders, BindingKind, BindingLayout, Buffer, CommandList, DescriptorSet, Device, Kernel,
    Location,
};
use crate::warptest::{self, AreaLight, AreaShape, Chart, Grid, Outcome, PlaneGrid, SphereGrid};

/// The radiance of the test's emitter (red is read back as the weight).
const RADIANCE: Vec3 = Vec3::new(2.0, 1.0, 0.5);

/// Where the test puts its shape: the map from the shape's local space to the world.
fn placement(shape: AreaShape) -> Affine3A {
    let rotate = Mat3::from_rotation_z(0.4) * Mat3::from_rotation_x(0.9);
    match shape {
        // Uneven scale: the world area is not the local one times a square.
        AreaShape::Fan => Affine3A::from_mat3_translation(
            rotate * Mat3::from_diagonal(Vec3::new(1.5, 0.6, 1.0)),
            Vec3::new(0.2, -0.3, 1.0),
        ),
        AreaShape::Disk => Affine3A::from_mat3_translation(
            rotate * Mat3::from_diagonal(Vec3::splat(0.7)),
            Vec3::new(-1.0, 0.5, 0.3),
        ),
        AreaShape::Sphere => Affine3A::from_mat3_translation(
            Mat3::from_diagonal(Vec3::splat(1.3)),
            Vec3::new(0.5, 0.0, -0.4),
        ),
    }
}

/// `m` as Mitsuba's `<matrix>` (row-major, 4 x 4).
fn matrix_xml(m: Affine3A) -> String {
    let c = glam::Mat4::from(m).transpose().to_cols_array();
    let v: Vec<String> = c.iter().map(|x| format!("{x:.9}")).collect();
    format!(
        r#"<transform name="to_world"><matrix value="{}"/></transform>"#,
        v.join(" ")
    )
}

/// The one-emitter scene of the test, loaded (as a user's would be) from files written
/// to a fresh folder under the system's temp dir, which is removed after.
fn scene(shape: AreaShape) -> Result<crate::scene::Scene> {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "wavetrace-warptest-{}-{}",
        std::process::id(),
        CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
    ));
    let scene = write_and_load(&dir, shape);
    let _ = std::fs::remove_dir_all(&dir);
    scene
}

/// [`scene`] in `dir`.
fn write_and_load(dir: &std::path::Path, shape: AreaShape) -> Result<crate::scene::Scene> {
    let io = |e: std::io::Error| {
        Error::Options(format!(
            "warptest: cannot write its test scene to {}: {e}",
            dir.display()
        ))
    };
    std::fs::create_dir_all(dir).map_err(io)?;
    let to_world = matrix_xml(placement(shape));
    let body = match shape {
        AreaShape::Fan => {
            // A fan from (0.3, -0.5) to the square's corners: areas 0.5, 0.7, 1.5, 1.3.
            let obj = "v 0.3 -0.5 0\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
                       f 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 2\n";
            std::fs::write(dir.join("fan.obj"), obj).map_err(io)?;
            format!(r#"<shape type="obj"><string name="filename" value="fan.obj"/>{to_world}"#)
        }
        AreaShape::Disk => format!(r#"<shape type="disk">{to_world}"#),
        AreaShape::Sphere => format!(r#"<shape type="sphere">{to_world}"#),
    };
    let xml = format!(
        r#"<scene version="3.0.0"><sensor type="perspective"/>{body}<emitter type="directionalarea"><rgb name="radiance" value="{}, {}, {}"/></emitter></shape></scene>"#,
        RADIANCE.x, RADIANCE.y, RADIANCE.z
    );
    let path = dir.join("scene.xml");
    std::fs::write(&path, xml).map_err(io)?;
    crate::scene::load(&path, &[])
        .map_err(|e| Error::Options(format!("warptest: its test scene does not load: {e}")))
}

/// The chart a shape's points are histogrammed in, with the map between it and the
/// world as [`placement`] puts the shape: the fan's square and the disk in the local
/// plane z = 0, the sphere's unit directions from its centre.
struct ShapeChart {
    shape: AreaShape,
    to_world: Affine3A,
}

impl ShapeChart {
    /// 32 x 32 cells of the square or disk; 32 x 24 of the sphere of directions.
    fn grid(&self) -> Grid {
        match self.shape {
            AreaShape::Fan => Grid::Plane(PlaneGrid {
                chart: Chart::Square,
                res: 32,
            }),
            AreaShape::Disk => Grid::Plane(PlaneGrid {
                chart: Chart::Disk,
                res: 32,
            }),
            AreaShape::Sphere => Grid::Sphere(SphereGrid::new(Vec3::Z, 32, 24)),
        }
    }

    /// The chart point of world point `p` on the shape.
    fn to_chart(&self, p: Vec3) -> Vec3 {
        let local = self.to_world.inverse().transform_point3(p);
        match self.shape {
            AreaShape::Sphere => local.normalize(),
            _ => Vec3::new(local.x, local.y, 0.0),
        }
    }

    /// The world point of chart point `q`.
    fn to_world(&self, q: Vec3) -> Vec3 {
        self.to_world.transform_point3(q)
    }

    /// World area per unit chart measure (area, or solid angle for the sphere).
    fn jacobian(&self) -> f64 {
        let m = self.to_world.matrix3;
        match self.shape {
            AreaShape::Sphere => (m.x_axis.length() as f64).powi(2),
            _ => m.x_axis.cross(m.y_axis).length() as f64,
        }
    }

    /// The shape's world area: the chart's measure (4 for the square, π for the disk,
    /// 4π for the sphere) times [`ShapeChart::jacobian`].
    fn area(&self) -> f64 {
        let measure = match self.shape {
            AreaShape::Fan => 4.0,
            AreaShape::Disk => std::f64::consts::PI,
            AreaShape::Sphere => 4.0 * std::f64::consts::PI,
        };
        measure * self.jacobian()
    }

    /// The shape's outward normal at world point `p` on it.
    fn normal(&self, p: Vec3) -> Vec3 {
        match self.shape {
            AreaShape::Sphere => (p - Vec3::from(self.to_world.translation)).normalize(),
            _ => {
                let m = self.to_world.matrix3;
                m.x_axis.cross(m.y_axis).normalize().into()
            }
        }
    }
}

/// The scene, its kernel and buffers, run in one of the kernel's modes.
struct Probe {
    device: Device,
    layout: BindingLayout,
    kernel: Kernel,
    buffers: SceneBuffers,
    frame: Buffer,
}

impl Probe {
    fn new(device: &Device, scene: &crate::scene::Scene) -> Result<Probe> {
        let bvh = Bvh::build(prims_from_scene(scene));
        let records = SceneRecords::new(scene, &bvh);
        let layout = BindingLayout::with_kinds(
            device,
            &[scene_binding_kinds(), vec![BindingKind::Storage; 3]],
            16,
        )?;
        let buffers = SceneBuffers::upload(device, &layout, &bvh, &records)?;
        let frame = Frame {
            emitter_count: records.emitters.len() as u32,
            env_emitter: records.env_emitter,
            ..Default::default()
        };
        let frame = Buffer::from_slice(device, "frame", &[frame])?;
        let kernel = Kernel::new(
            device,
            "emitter_ray",
            shaders::TESTS_EMITTER_RAY,
            &layout,
            &FlatPrims::of(&bvh, 0).constants(),
        )?;
        Ok(Probe {
            device: device.clone(),
            layout,
            kernel,
            buffers,
            frame,
        })
    }

    /// `count` items of `mode` (0: two vec4 per sample; else one per point).
    fn run(
        &self,
        mode: u32,
        count: u32,
        seed: u32,
        points: &[[f32; 4]],
    ) -> crate::gpu::Result<Vec<[f32; 4]>> {
        let per = if mode == 0 { 2 } else { 1 };
        let out = Buffer::new(
            &self.device,
            "emitter rays",
            (count as u64 * per).max(1) * 16,
            Location::Gpu,
        )?;
        let input = Buffer::from_slice(
            &self.device,
            "points",
            if points.is_empty() {
                &[[0.0f32; 4]][..]
            } else {
                points
            },
        )?;
        let set = DescriptorSet::new(&self.layout, 1, &[&self.frame, &out, &input])?;
        let push = [count, seed, mode, 0];
        let mut cmd = CommandList::new(&self.device)?;
        cmd.dispatch(
            &self.kernel,
            &[&self.buffers.set, &set],
            bytemuck::cast_slice(&push),
            [count.div_ceil(64), 1, 1],
        );
        cmd.submit_and_wait()?;
        let mut v: Vec<[f32; 4]> = out.read(&self.device)?;
        v.truncate(count as usize * per as usize);
        Ok(v)
    }
}

/// Tests the light rays of a directionalarea emitter on `light.shape` with `n`
/// samples (see the module's doc).
pub fn test_directional_area(
    device: &Device,
    light: AreaLight,
    n: u32,
    seed: u32,
) -> Result<Outcome> {
    let chart = ShapeChart {
        shape: light.shape,
        to_world: placement(light.shape),
    };
    let probe = Probe::new(device, &scene(light.shape)?)?;
    let grid = chart.grid();
    let raw = probe.run(0, n, seed, &[])?;
    let area = chart.area();
    let points: Vec<Vec3> = raw
        .chunks(2)
        .map(|s| {
            let p = Vec3::new(s[0][0], s[0][1], s[0][2]);
            let (pdf, dir, weight) = (s[0][3], Vec3::new(s[1][0], s[1][1], s[1][2]), s[1][3]);
            let along_normal = dir.dot(chart.normal(p)) > 1.0 - 1e-4;
            // radiance x area, and a density 1 / area, of the shape as placed.
            let weighted = (weight as f64 / (RADIANCE.x as f64 * area) - 1.0).abs() < 1e-4
                && (pdf as f64 * area - 1.0).abs() < 1e-4;
            if along_normal && weighted {
                chart.to_chart(p)
            } else {
                Vec3::NAN
            }
        })
        .collect();
    let jacobian = chart.jacobian();
    let mode = if light.mismatched { 2 } else { 1 };
    let expected = warptest::expected_counts(&grid, n as usize, |q| {
        let world: Vec<[f32; 4]> = q
            .iter()
            .map(|q| {
                let w = chart.to_world(Vec3::new(q[0], q[1], q[2]));
                [w.x, w.y, w.z, 0.0]
            })
            .collect();
        let pdf = probe.run(mode, world.len() as u32, 0, &world)?;
        Ok(pdf.iter().map(|v| v[0] as f64 * jacobian).collect())
    })?;
    Ok(warptest::finish(grid, points, n as usize, 0, expected))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chart round-trips, and its area (the chart's measure times its area
    /// element) is the one the host puts in the emitter's record (which the kernel's
    /// density reads).
    #[test]
    fn charts_measure_the_recorded_area() {
        for shape in [AreaShape::Fan, AreaShape::Disk, AreaShape::Sphere] {
            let chart = ShapeChart {
                shape,
                to_world: placement(shape),
            };
            let scene = scene(shape).unwrap();
            let bvh = Bvh::build(prims_from_scene(&scene));
            let records = SceneRecords::new(&scene, &bvh);
            let area = records.emitters[0].area as f64;
            let want = chart.area();
            assert!(
                (area - want).abs() < 1e-4 * want,
                "{shape:?}: {area} vs {want}"
            );
            let q = match shape {
                AreaShape::Sphere => Vec3::new(0.3, -0.5, 0.6).normalize(),
                _ => Vec3::new(0.3, -0.5, 0.0),
            };
            let back = chart.to_chart(chart.to_world(q));
            assert!((back - q).length() < 1e-5, "{shape:?}: {back} vs {q}");
        }
    }
}
