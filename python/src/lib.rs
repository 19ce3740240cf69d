//! `wavetrace._wavetrace`: the Rust side of the `wavetrace` Python package
//! (docs/python.md). The Python side (`wavetrace/__init__.py`) wraps these in the
//! public API: NumPy arrays, `load_dict`, `_repr_png_`.
//!
//! A [`Scene`] holds the loaded scene and, once rendered, its [`Renderer`] (BVH,
//! buffers and kernels on the device), kept between renders: a new seed, sample count
//! or camera reuses it; another integrator or a changed emitter or BSDF sets it up
//! again. Renders run with the GIL released; after every batch the progress callback
//! (if any) is called and pending signals are checked, so Ctrl-C raises
//! `KeyboardInterrupt` within a batch and leaves the scene ready for the next render.
//! Every error is a Python exception; a panic is caught and raised as `RuntimeError`.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Duration;

use glam::{Mat4, Vec2, Vec3};
use pyo3::exceptions::{PyIndexError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyDict, PyList};

use wavetrace::gpu::{Device, DeviceKind};
use wavetrace::render::film::FilmSums;
use wavetrace::render::job::{self, JobControl};
use wavetrace::render::partial::SampleRanges;
use wavetrace::render::{RenderOptions, Renderer};
use wavetrace::scene::bsdf::Bsdf;
use wavetrace::scene::emitter::Emitter;

/// Runs `f`, turning a panic into a `RuntimeError` (no panic crosses into Python).
fn guarded<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => {
            let what = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".to_string());
            Err(PyRuntimeError::new_err(format!(
                "internal error in wavetrace (please report): {what}"
            )))
        }
    }
}

fn runtime(e: impl std::fmt::Display) -> PyErr {
    PyRuntimeError::new_err(e.to_string())
}

/// Makes a value that is used on one thread at a time movable into
/// `allow_threads` (the renderer holds Vulkan handles, which ash marks neither).
struct OnOneThread<T>(T);
// SAFETY: the value is only used by the thread that holds the `Scene` borrow (PyO3
// borrows a pyclass exclusively for `&mut self`); `allow_threads` runs the closure on
// the calling thread.
unsafe impl<T> Send for OnOneThread<T> {}

/// The devices wavetrace can render on: (index, name, kind).
#[pyfunction]
fn devices() -> PyResult<Vec<(usize, String, String)>> {
    guarded(|| {
        let list = Device::list().map_err(runtime)?;
        Ok(list
            .into_iter()
            .map(|d| (d.index, d.name, format!("{:?}", d.kind)))
            .collect())
    })
}

/// A loaded scene, with its renderer once rendered.
#[pyclass(module = "wavetrace._wavetrace", unsendable)]
struct Scene {
    scene: wavetrace::scene::Scene,
    /// The `device=` selector (index or part of a name); `None`: the best one.
    selector: Option<String>,
    device: Option<Device>,
    /// The renderer and the (integrator option, samples per pixel) it was set up for.
    renderer: Option<((Option<String>, u32), Renderer)>,
}

/// A mesh built in Python (`wavetrace.Mesh`): name, positions (float32 x 3 per
/// vertex), faces (uint32 x 3), normals and texcoords (float32 x 3 and x 2, or
/// empty), attributes (name, channels, float32 values), all native byte order.
type MeshParts<'py> = (
    String,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Vec<(String, u32, Bound<'py, PyBytes>)>,
);

fn mesh_of(parts: &MeshParts<'_>) -> wavetrace::scene::Mesh {
    use wavetrace::scene::texture::mesh_attribute::MeshAttribute;
    let (name, positions, faces, normals, uvs, attributes) = parts;
    let floats =
        |b: &Bound<'_, PyBytes>| -> Vec<f32> { bytemuck::pod_collect_to_vec(b.as_bytes()) };
    let p = floats(positions);
    let n = floats(normals);
    let t = floats(uvs);
    let f: Vec<u32> = bytemuck::pod_collect_to_vec(faces.as_bytes());
    wavetrace::scene::Mesh {
        name: name.clone(),
        positions: p.chunks_exact(3).map(Vec3::from_slice).collect(),
        normals: n.chunks_exact(3).map(Vec3::from_slice).collect(),
        uvs: t.chunks_exact(2).map(Vec2::from_slice).collect(),
        indices: f.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        attributes: attributes
            .iter()
            .map(|(name, dim, values)| MeshAttribute {
                name: name.clone(),
                dim: *dim,
                values: floats(values),
            })
            .collect(),
        ..Default::default()
    }
}

/// Loads the scene file `path` with `-D` overrides `defines`; `<shape type="mesh">`
/// shapes in it name `meshes` (built in Python) by index, handed to the loader in
/// memory (`wavetrace::scene::shape::provided`).
#[pyfunction]
#[pyo3(signature = (path, defines, device=None, meshes=Vec::new()))]
fn load_file(
    py: Python<'_>,
    path: PathBuf,
    defines: Vec<(String, String)>,
    device: Option<String>,
    meshes: Vec<MeshParts<'_>>,
) -> PyResult<Scene> {
    guarded(|| {
        let meshes: Vec<wavetrace::scene::Mesh> = meshes.iter().map(mesh_of).collect();
        let scene = py
            .allow_threads(move || {
                if meshes.is_empty() {
                    wavetrace::scene::load(&path, &defines)
                } else {
                    wavetrace::scene::shape::provided::load(&path, &defines, meshes)
                }
            })
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Scene {
            scene,
            selector: device,
            device: None,
            renderer: None,
        })
    })
}

fn mat4_from_rows(rows: &[Vec<f32>]) -> PyResult<Mat4> {
    if rows.len() != 4 || rows.iter().any(|r| r.len() != 4) {
        return Err(PyValueError::new_err(
            "to_world must be a 4x4 matrix (nested lists or a NumPy array)",
        ));
    }
    let m = Mat4::from_cols_array_2d(&[
        [rows[0][0], rows[1][0], rows[2][0], rows[3][0]],
        [rows[0][1], rows[1][1], rows[2][1], rows[3][1]],
        [rows[0][2], rows[1][2], rows[2][2], rows[3][2]],
        [rows[0][3], rows[1][3], rows[2][3], rows[3][3]],
    ]);
    if !m.is_finite() {
        return Err(PyValueError::new_err("to_world holds a NaN or infinity"));
    }
    Ok(m)
}

fn rgb(value: [f32; 3], what: &str) -> PyResult<Vec3> {
    let v = Vec3::from(value);
    if !v.is_finite() || v.min_element() < 0.0 {
        return Err(PyValueError::new_err(format!(
            "{what} must be three finite non-negative numbers, got {value:?}"
        )));
    }
    Ok(v)
}

/// The name of a BSDF's kind, as `info()` lists it.
fn bsdf_name(b: &Bsdf) -> String {
    let dbg = format!("{b:?}");
    dbg.split(|c: char| !c.is_alphanumeric())
        .next()
        .unwrap_or("")
        .to_lowercase()
}

/// The colour parameter `set_bsdf_color` changes in `b`, if it has one.
fn bsdf_color(b: &mut Bsdf) -> Option<&mut Vec3> {
    match b {
        Bsdf::Diffuse(d) => Some(&mut d.reflectance),
        Bsdf::TwoSided(inner) => bsdf_color(inner),
        _ => None,
    }
}

impl Scene {
    fn device(&mut self) -> PyResult<Device> {
        if self.device.is_none() {
            self.device = Some(Device::new(self.selector.as_deref()).map_err(runtime)?);
        }
        self.device
            .clone()
            .ok_or_else(|| PyRuntimeError::new_err("no device"))
    }

    /// The renderer for `integrator` and renders of `spp` samples per pixel, set up
    /// if there is none for them. The sample count is part of the key as it is the
    /// CLI's `expected_spp`: it decides the schedule (on a CPU device, whether the
    /// first bounce runs fused), and so the image's last bits.
    fn renderer(
        &mut self,
        py: Python<'_>,
        integrator: Option<String>,
        spp: u32,
    ) -> PyResult<&mut Renderer> {
        let key = (integrator, spp);
        if self.renderer.as_ref().is_none_or(|(k, _)| *k != key) {
            self.renderer = None;
            let device = self.device()?;
            // Batches short enough on a CPU device for Ctrl-C to stop a render within
            // a second (the image is the same bits whatever the batches).
            let cpu = device.info().kind == DeviceKind::Cpu;
            let options = RenderOptions {
                integrator: key.0.clone(),
                expected_spp: Some(spp),
                max_batch_paths: cpu.then_some(CPU_BATCH_PATHS),
                ..RenderOptions::default()
            };
            let scene = OnOneThread(&self.scene);
            let made = py.allow_threads(move || {
                let scene = scene;
                OnOneThread(Renderer::new(&device, scene.0, &options))
            });
            let r = made.0.map_err(|e| PyValueError::new_err(e.to_string()))?;
            self.renderer = Some((key, r));
        }
        match &mut self.renderer {
            Some((_, r)) => Ok(r),
            None => Err(PyRuntimeError::new_err("no renderer")),
        }
    }
}

/// Most paths per batch on a CPU device (lavapipe renders about that many in a
/// quarter of a second on two cores): the most a Ctrl-C waits.
const CPU_BATCH_PATHS: u32 = 1 << 17;

/// What the render loop shares with the callbacks.
struct Watch {
    progress: Option<PyObject>,
    /// The first error a callback or a signal handler raised.
    error: Mutex<Option<PyErr>>,
    stop: AtomicBool,
}

impl Watch {
    /// Runs the pending signal handlers and the progress callback; an exception in
    /// either stops the render.
    fn tick(&self, done: u64, total: u64) {
        if self.stop.load(Ordering::SeqCst) {
            return;
        }
        let r = Python::with_gil(|py| -> PyResult<()> {
            py.check_signals()?;
            if let Some(cb) = &self.progress {
                cb.call1(py, (done, total))?;
            }
            Ok(())
        });
        if let Err(e) = r {
            if let Ok(mut slot) = self.error.lock() {
                slot.get_or_insert(e);
            }
            self.stop.store(true, Ordering::SeqCst);
        }
    }
}

#[pymethods]
impl Scene {
    /// Shapes, triangles, emitters, BSDFs, film size, sample count, integrator.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.scene;
        let d = PyDict::new(py);
        d.set_item("path", s.path.display().to_string())?;
        d.set_item("shapes", s.meshes.len() + s.quadrics.len())?;
        d.set_item("meshes", s.meshes.len())?;
        d.set_item("quadrics", s.quadrics.len())?;
        d.set_item("triangles", s.triangle_count())?;
        d.set_item("emitters", s.emitters.len())?;
        let emitters: Vec<String> = s
            .emitters
            .iter()
            .map(|e| {
                format!("{e:?}")
                    .split(|c: char| !c.is_alphanumeric())
                    .next()
                    .unwrap_or("")
                    .to_lowercase()
            })
            .collect();
        d.set_item("emitter_types", emitters)?;
        let bsdfs: Vec<String> = s.bsdfs.iter().map(bsdf_name).collect();
        d.set_item("bsdfs", bsdfs)?;
        d.set_item("film_size", (s.camera.width, s.camera.height))?;
        d.set_item("channels", s.film.pixel_format.channel_names().to_vec())?;
        d.set_item("spp", s.spp)?;
        d.set_item("integrator", &s.integrator.name)?;
        d.set_item("fov", s.camera.fov_x_deg)?;
        d.set_item("features", s.features())?;
        if let Some(dev) = &self.device {
            d.set_item("device", dev.info().to_string())?;
        }
        Ok(d)
    }

    /// The camera-to-world matrix as 4 rows.
    fn camera_to_world(&self) -> Vec<Vec<f32>> {
        let c = self.scene.camera.to_world.to_cols_array_2d();
        (0..4).map(|r| (0..4).map(|k| c[k][r]).collect()).collect()
    }

    /// Moves the camera (`to_world`: 4 rows of 4; `fov`: horizontal, degrees) without
    /// setting the scene up again.
    #[pyo3(signature = (to_world=None, fov=None))]
    fn set_camera(&mut self, to_world: Option<Vec<Vec<f32>>>, fov: Option<f32>) -> PyResult<()> {
        guarded(|| {
            let m = match &to_world {
                Some(rows) => mat4_from_rows(rows)?,
                None => self.scene.camera.to_world,
            };
            let f = fov.unwrap_or(self.scene.camera.fov_x_deg);
            if !(f.is_finite() && f > 0.0 && f < 180.0) {
                return Err(PyValueError::new_err(format!(
                    "fov must be in (0, 180) degrees, got {f}"
                )));
            }
            if let Some((_, r)) = &mut self.renderer {
                r.set_camera(m, f)
                    .map_err(|e| PyValueError::new_err(e.to_string()))?;
            }
            self.scene.camera.to_world = m;
            self.scene.camera.fov_x_deg = f;
            Ok(())
        })
    }

    /// Sets the radiance of emitter `index` (area and constant emitters) or the
    /// intensity of a point or spot light; the next render sets the scene up again.
    fn set_emitter_radiance(&mut self, index: usize, value: [f32; 3]) -> PyResult<()> {
        let v = rgb(value, "radiance")?;
        let n = self.scene.emitters.len();
        let e = self.scene.emitters.get_mut(index).ok_or_else(|| {
            PyIndexError::new_err(format!("emitter {index}: the scene has {n} emitters"))
        })?;
        match e {
            Emitter::Area { radiance } | Emitter::Constant { radiance } => *radiance = v,
            Emitter::Point { intensity, .. } | Emitter::Spot { intensity, .. } => *intensity = v,
            other => {
                return Err(PyValueError::new_err(format!(
                    "emitter {index} ({}) has no single radiance to set",
                    format!("{other:?}").split('{').next().unwrap_or("").trim()
                )))
            }
        }
        self.renderer = None;
        Ok(())
    }

    /// Sets the colour (reflectance) of BSDF `index` (`diffuse`, also inside
    /// `twosided`); the next render sets the scene up again.
    fn set_bsdf_color(&mut self, index: usize, value: [f32; 3]) -> PyResult<()> {
        let v = rgb(value, "reflectance")?;
        let n = self.scene.bsdfs.len();
        let b = self.scene.bsdfs.get_mut(index).ok_or_else(|| {
            PyIndexError::new_err(format!("BSDF {index}: the scene has {n} BSDFs"))
        })?;
        let name = bsdf_name(b);
        let c = bsdf_color(b).ok_or_else(|| {
            PyValueError::new_err(format!(
                "BSDF {index} ({name}) has no colour this version can set (diffuse only)"
            ))
        })?;
        *c = v;
        self.renderer = None;
        Ok(())
    }

    /// Renders `spp` samples per pixel (`None`: the scene's) with `seed` and returns
    /// (height, width, channel names, float32 pixels as a bytearray).
    #[pyo3(signature = (spp=None, seed=0, integrator=None, progress=None))]
    fn render<'py>(
        &mut self,
        py: Python<'py>,
        spp: Option<u32>,
        seed: u32,
        integrator: Option<String>,
        progress: Option<PyObject>,
    ) -> PyResult<(u32, u32, Bound<'py, PyList>, Bound<'py, PyByteArray>)> {
        guarded(|| {
            let spp = spp.unwrap_or(self.scene.spp);
            if spp == 0 {
                return Err(PyValueError::new_err("spp must be at least 1"));
            }
            let format = self.scene.film.pixel_format;
            let (to_world, fov) = (self.scene.camera.to_world, self.scene.camera.fov_x_deg);
            let renderer = self.renderer(py, integrator, spp)?;
            renderer.set_seed(seed).map_err(runtime)?;
            renderer.set_camera(to_world, fov).map_err(runtime)?;
            let count = renderer
                .round_sample_count(spp)
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            let n = count.count;
            renderer.set_sample_count(count).map_err(runtime)?;
            let watch = Watch {
                progress,
                error: Mutex::new(None),
                stop: AtomicBool::new(false),
            };
            let sums = render_job(py, renderer, n, &watch)?;
            if let Some(e) = watch.error.lock().ok().and_then(|mut e| e.take()) {
                return Err(e);
            }
            let sums = sums.ok_or_else(|| PyRuntimeError::new_err("nothing was rendered"))?;
            let (names, data) = sums.channels(format);
            let bytes = PyByteArray::new(py, bytemuck::cast_slice(&data));
            Ok((sums.height(), sums.width(), PyList::new(py, names)?, bytes))
        })
    }
}

/// Renders samples `0..n` on `renderer` with the GIL released, `watch` ticked after
/// every batch; `None` if stopped before a sample was done.
fn render_job(
    py: Python<'_>,
    renderer: &mut Renderer,
    n: u32,
    watch: &Watch,
) -> PyResult<Option<FilmSums>> {
    let ranges = SampleRanges::of(0..n);
    let done = SampleRanges::default();
    let stop = &watch.stop;
    let tick = |d: u64, t: u64| watch.tick(d, t);
    let never = |_: &FilmSums, _: &SampleRanges| Ok(());
    let nothing = |_: u64, _: u64| {};
    let work = OnOneThread((renderer, &ranges, &done, &tick, &never, &nothing, stop));
    let result = py.allow_threads(move || {
        let work = work;
        let (renderer, ranges, done, tick, never, nothing, stop) = work.0;
        let control = JobControl {
            stop,
            checkpoint_every: None::<Duration>,
            checkpoint: never,
            boundary: nothing,
            progress: tick,
            preview: None,
        };
        OnOneThread(job::render_on_one(renderer, ranges, None, done, &control))
    });
    let r = result.0.map_err(runtime)?;
    Ok(r.sums)
}

/// The Mitsuba plugin types of the catalogue: (type, XML tag, supported).
#[pyfunction]
fn plugins() -> Vec<(&'static str, &'static str, bool)> {
    use wavetrace::scene::plugin::{catalogue, Support};
    use wavetrace::scene::xml::Dialect;
    catalogue()
        .into_iter()
        .filter(|d| d.dialect == Dialect::Mitsuba)
        .map(|d| (d.name, d.family.tag(), d.support == Support::Yes))
        .collect()
}

/// Writes `data` (height x width x channels float32 bytes, native order, row-major, channel `names`) to
/// `path`: OpenEXR (float32, or half with `half`), PFM, or an sRGB PNG, by extension.
#[pyfunction]
#[pyo3(signature = (path, width, height, names, data, half=false))]
fn write(
    path: PathBuf,
    width: u32,
    height: u32,
    names: Vec<String>,
    data: &[u8],
    half: bool,
) -> PyResult<()> {
    guarded(|| {
        let data: Vec<f32> = bytemuck::pod_collect_to_vec(data);
        let c = names.len();
        if c == 0 || data.len() != width as usize * height as usize * c {
            return Err(PyValueError::new_err(format!(
                "image of {width}x{height} with {c} channels needs {} values, got {}",
                width as usize * height as usize * c,
                data.len()
            )));
        }
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_lowercase())
            .unwrap_or_default();
        let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let r = match ext.as_str() {
            "exr" => wavetrace::image::exr::write_channels_with_text(
                &path,
                width,
                height,
                &name_refs,
                &data,
                if half {
                    wavetrace::image::exr::Precision::Half
                } else {
                    wavetrace::image::exr::Precision::Float
                },
                &[],
            ),
            "pfm" => wavetrace::image::pfm::write(&path, width, height, c, &data),
            "png" => wavetrace::image::png::write_channels(&path, width, height, c, &data, 0.0),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "{}: write() writes .exr, .pfm or .png",
                    path.display()
                )))
            }
        };
        r.map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))
    })
}

/// Reads an OpenEXR file: (height, width, channel names, float32 pixels).
#[pyfunction]
fn read_exr(
    py: Python<'_>,
    path: PathBuf,
) -> PyResult<(u32, u32, Vec<String>, Bound<'_, PyByteArray>)> {
    guarded(|| {
        let (w, h, channels) = wavetrace::image::exr::read_channels(&path)
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
        let n = w as usize * h as usize;
        let mut data = Vec::with_capacity(n * channels.len());
        for i in 0..n {
            data.extend(channels.iter().map(|c| c.values[i]));
        }
        let names = channels.iter().map(|c| c.name.clone()).collect();
        Ok((
            h,
            w,
            names,
            PyByteArray::new(py, bytemuck::cast_slice(&data)),
        ))
    })
}

#[pymodule]
fn _wavetrace(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(devices, m)?)?;
    m.add_function(wrap_pyfunction!(load_file, m)?)?;
    m.add_function(wrap_pyfunction!(write, m)?)?;
    m.add_function(wrap_pyfunction!(read_exr, m)?)?;
    m.add_function(wrap_pyfunction!(plugins, m)?)?;
    m.add_class::<Scene>()?;
    Ok(())
}
