//! `wavetrace view`: a window that shows the film converge while the wavefront
//! renders, and lets the camera move.
//!
//! One thread runs a loop: handle the window's events ([`controls`]), render one
//! step of at most a frame's worth of paths ([`Renderer::step`], the batches of a
//! headless render), tone map the film's running mean on the GPU ([`picture`]) and
//! present it ([`crate::gpu::Swapchain`]). The step's size adapts so a frame takes
//! about [`FRAME_SECONDS`], which keeps the window answering input several times a
//! second even on two CPU cores with lavapipe. A camera change restarts the film;
//! the window can be resized freely (the film keeps its resolution, letterboxed).
//!
//! The viewer drives `render/` through the API `render` itself uses; nothing in
//! `render/` knows of it.

pub mod camera;
pub mod controls;
pub mod error;
pub mod picture;
pub mod window;

pub use error::{Error, Result};

use std::path::{Path, PathBuf};
use std::time::Instant;

use glfw::WindowEvent;

use crate::gpu::{Device, Presented, SurfaceRequest, Swapchain};
use crate::render::{RenderOptions, Renderer};
use crate::scene::film::{FileFormat, PixelFormat};
use crate::scene::Scene;

use camera::CameraRig;
use controls::{Controls, Request};
use picture::Picture;
use window::Window;

/// The render time a frame aims at: the step's path count adapts to it.
pub const FRAME_SECONDS: f64 = 0.06;
/// Paths of the first step, before the time of one is known, and the fewest a step
/// renders.
const FIRST_STEP_PATHS: u32 = 4096;
const MIN_STEP_PATHS: u32 = 256;
/// How often the title is updated, in seconds.
const TITLE_SECONDS: f64 = 0.25;

/// How to run the viewer.
#[derive(Debug, Clone, Default)]
pub struct ViewOptions {
    /// Samples per pixel to stop at (rounded as the sampler rounds them); `None`:
    /// render until the window closes.
    pub spp: Option<u32>,
    /// Stops of exposure of the display (the film is not changed).
    pub exposure: f32,
    /// Render `spp` samples (the scene's count without `spp`), save what the window
    /// shows to this PNG, and exit.
    pub screenshot: Option<PathBuf>,
    /// Vulkan device: index or part of its name.
    pub device: Option<String>,
    pub render: RenderOptions,
    /// Where F12 / P saves `<scene>-<spp>spp.exr` and `.png`.
    pub save_dir: PathBuf,
}

/// What a session of the viewer did, for the closing message.
#[derive(Debug, Clone, Default)]
pub struct ViewReport {
    pub device: String,
    /// From the start of the program (the `started` given to [`run`]) to the first
    /// frame on screen.
    pub first_frame_seconds: f64,
    /// Frames presented while rendering, and the time they took.
    pub render_frames: u64,
    pub render_seconds: f64,
    /// Camera paths (samples) rendered in that time.
    pub samples: u64,
    /// Samples per pixel of the last accumulation.
    pub spp: u32,
    /// Files written (screenshots and saves).
    pub written: Vec<PathBuf>,
}

impl ViewReport {
    pub fn frames_per_second(&self) -> f64 {
        self.render_frames as f64 / self.render_seconds.max(1e-9)
    }

    pub fn samples_per_second(&self) -> f64 {
        self.samples as f64 / self.render_seconds.max(1e-9)
    }
}

/// The accumulation since the last camera change.
struct Accumulation {
    progress: crate::render::progressive::Progressive,
    started: Instant,
    /// Paths rendered and seconds spent stepping.
    paths: u64,
    /// Wall time at which the last sample finished.
    finished: Option<f64>,
}

impl Accumulation {
    fn start(renderer: &mut Renderer, end: Option<u32>) -> Result<Accumulation> {
        Ok(Accumulation {
            progress: renderer.start_progressive(end)?,
            started: Instant::now(),
            paths: 0,
            finished: None,
        })
    }

    fn elapsed(&self) -> f64 {
        self.finished
            .unwrap_or_else(|| self.started.elapsed().as_secs_f64())
    }
}

/// Opens the window on `scene` and runs until Esc, the window's close button, or
/// (with a screenshot) the last sample. `log` receives messages for the user;
/// `started` is when the program started (for the time to the first frame).
pub fn run(
    scene: &Scene,
    options: &ViewOptions,
    started: Instant,
    log: &mut dyn FnMut(String),
) -> Result<ViewReport> {
    let crop = scene.film.crop;
    let title = format!("wavetrace: {}", file_name(scene, false, "scene"));
    let (w, h) = crop.map_or((scene.camera.width, scene.camera.height), |c| {
        (c.width, c.height)
    });
    // Declared first, dropped last: the surface (held by the device) goes first.
    // The window opens before the scene is set up on the device (pipelines and the
    // first dispatches take seconds on lavapipe): say so meanwhile.
    let mut window = Window::open(&format!("{title} | setting up"), w, h)?;
    let extensions = window.instance_extensions()?;
    let device = open_device(&window, &extensions, options.device.as_deref())?;
    let mut report = ViewReport {
        device: device.info().to_string(),
        ..Default::default()
    };
    log(format!("device: {}", device.info()));
    let mut renderer = Renderer::new(&device, scene, &options.render)?;
    let end = sample_end(&mut renderer, scene, options, log)?;
    let luminance = matches!(
        scene.film.pixel_format,
        PixelFormat::Luminance | PixelFormat::LuminanceAlpha
    );
    let picture = Picture::new(&device, &renderer, luminance)?;
    let film_size = (picture.width, picture.height);
    let mut swapchain = Swapchain::new(&device, window.framebuffer_size(), film_size)?;
    log(format!(
        "window: {} ({}x{} film, '{}'); keys: WASDQE move, arrows turn, drag orbits, \
         scroll zooms, =/- speed, [/] exposure, R reset, P/F12 save, Esc quit",
        swapchain.describe(),
        film_size.0,
        film_size.1,
        renderer.integrator().name()
    ));
    let mut controls = Controls::new(CameraRig::of_scene(scene), options.exposure);
    let mut acc = Accumulation::start(&mut renderer, end)?;
    let capacity = renderer.capacity();
    let mut budget = FIRST_STEP_PATHS.min(capacity);
    let mut stale = false;
    let mut dirty = true;
    let mut last_title: Option<Instant> = None;
    let stem = file_name(scene, true, "view");

    loop {
        let iteration = Instant::now();
        window.glfw.poll_events();
        let mut moved = false;
        let mut requests = Vec::new();
        for (_, event) in glfw::flush_messages(&window.events) {
            match event {
                WindowEvent::FramebufferSize(..) => stale = true,
                WindowEvent::Refresh => dirty = true,
                _ => {}
            }
            let changed = controls.handle(&event);
            moved |= changed.camera;
            dirty |= changed.exposure;
            requests.extend(changed.request);
        }
        if window.window.should_close() {
            requests.push(Request::Quit);
        }
        if moved {
            renderer.set_camera(controls.camera.to_world(), controls.camera.fov_deg)?;
            acc = Accumulation::start(&mut renderer, end)?;
            dirty = true;
            // Show the restart at once.
            window
                .window
                .set_title(&title_line(&title, &acc, end, controls.exposure));
            last_title = Some(Instant::now());
        }

        let rendering = !acc.progress.finished();
        if rendering {
            budget = step(&mut renderer, &mut acc, budget, &mut report)?;
            dirty = true;
        }
        let shown = redraw(
            &window,
            &mut swapchain,
            &picture,
            &controls,
            &mut stale,
            &mut dirty,
        )?;
        if shown {
            if report.first_frame_seconds == 0.0 {
                report.first_frame_seconds = started.elapsed().as_secs_f64();
                log(format!(
                    "first frame {:.2} s after start",
                    report.first_frame_seconds
                ));
            }
            if rendering {
                report.render_frames += 1;
            }
        }
        if rendering {
            // Events, step, tone mapping and present: the whole frame.
            report.render_seconds += iteration.elapsed().as_secs_f64();
        }
        report.spp = acc.progress.samples_done();

        if last_title.is_none_or(|t| t.elapsed().as_secs_f64() >= TITLE_SECONDS)
            || acc.progress.finished()
        {
            window
                .window
                .set_title(&title_line(&title, &acc, end, controls.exposure));
            last_title = Some(Instant::now());
        }

        for request in requests {
            match request {
                Request::Quit => return Ok(report),
                Request::Save => {
                    let (exr, png) = save_names(&options.save_dir, &stem, report.spp);
                    save(&renderer, &picture, scene, &exr, &png)?;
                    log(format!("saved {} and {}", exr.display(), png.display()));
                    report.written.extend([exr, png]);
                }
            }
        }

        if acc.progress.finished() {
            if let Some(path) = &options.screenshot {
                picture.write_png(path)?;
                log(format!(
                    "wrote {} ({} spp)",
                    path.display(),
                    acc.progress.samples_done()
                ));
                report.written.push(path.clone());
                return Ok(report);
            }
            if !dirty && !stale {
                // Nothing to render: sleep until an event (or a moment passes).
                window.glfw.wait_events_timeout(TITLE_SECONDS);
            }
        }
    }
}

/// Shows the picture if anything changed (tone mapping it again if the film or the
/// exposure did), remaking the swapchain when the window changed. Returns whether a
/// frame reached the screen.
fn redraw(
    window: &Window,
    swapchain: &mut Swapchain,
    picture: &Picture,
    controls: &Controls,
    stale: &mut bool,
    dirty: &mut bool,
) -> Result<bool> {
    if !*stale && !*dirty {
        return Ok(false);
    }
    if *dirty {
        picture.develop(controls.exposure)?;
        *dirty = false;
    }
    let size = window.framebuffer_size();
    if size.0 == 0 || size.1 == 0 {
        // Minimized: show it when it comes back (a size event).
        return Ok(false);
    }
    if *stale || swapchain.extent() != size {
        swapchain.resize(size)?;
        *stale = false;
    }
    match swapchain.present(&picture.pixels)? {
        Presented::Shown => Ok(true),
        Presented::Stale => {
            *stale = true;
            Ok(false)
        }
    }
}

/// The window's title: scene, samples per pixel, time and speed of the accumulation,
/// exposure.
fn title_line(title: &str, acc: &Accumulation, end: Option<u32>, exposure: f32) -> String {
    let seconds = acc.elapsed();
    let rate = acc.paths as f64 / seconds.max(1e-9) / 1e6;
    let spp = match end {
        Some(e) => format!("{}/{e} spp", acc.progress.samples_done()),
        None => format!("{} spp", acc.progress.samples_done()),
    };
    let state = if acc.progress.finished() {
        ", done"
    } else {
        ""
    };
    let exposure = if exposure != 0.0 {
        format!(" | exposure {exposure:+.1}")
    } else {
        String::new()
    };
    format!("{title} | {spp}{state} | {seconds:.1} s | {rate:.2} M samples/s{exposure}")
}

/// `<dir>/<stem>-<spp>spp.exr` and `.png`, with `-2`, `-3`, ... added if taken.
fn save_names(dir: &Path, stem: &str, spp: u32) -> (PathBuf, PathBuf) {
    let mut n = 1;
    loop {
        let base = if n == 1 {
            format!("{stem}-{spp}spp")
        } else {
            format!("{stem}-{spp}spp-{n}")
        };
        let exr = dir.join(format!("{base}.exr"));
        let png = dir.join(format!("{base}.png"));
        if !exr.exists() && !png.exists() {
            return (exr, png);
        }
        n += 1;
    }
}

/// Saves the film as it stands: a linear EXR (the scene's pixel and component
/// formats) and the PNG the window shows.
fn save(
    renderer: &Renderer,
    picture: &Picture,
    scene: &Scene,
    exr: &Path,
    png: &Path,
) -> Result<()> {
    let film = renderer.read_film()?;
    film.write(
        exr,
        scene.film.pixel_format,
        scene.film.component_format,
        FileFormat::OpenExr,
        None,
    )?;
    picture.write_png(png)?;
    Ok(())
}

/// The scene file's name (its stem with `stem`), or `otherwise`.
fn file_name(scene: &Scene, stem: bool, otherwise: &str) -> String {
    let name = if stem {
        scene.path.file_stem()
    } else {
        scene.path.file_name()
    };
    name.map_or_else(|| otherwise.into(), |n| n.to_string_lossy().into_owned())
}

/// The device of `window`, presenting to its surface (`name`: `--device`).
fn open_device(window: &Window, extensions: &[String], name: Option<&str>) -> Result<Device> {
    let mut create = |instance: u64| window.create_surface(instance);
    Ok(Device::with_surface(
        name,
        SurfaceRequest {
            instance_extensions: extensions,
            create: &mut create,
        },
    )?)
}

/// The sample count the view stops at (`--spp`, or the scene's for a screenshot;
/// `None`: it goes on), set on `renderer`; logs the sampler's rounding and what of the
/// film the integrator does not render.
fn sample_end(
    renderer: &mut Renderer,
    scene: &Scene,
    options: &ViewOptions,
    log: &mut dyn FnMut(String),
) -> Result<Option<u32>> {
    let spp = options
        .spp
        .or_else(|| options.screenshot.is_some().then_some(scene.spp));
    let end = match spp {
        Some(spp) => {
            let count = renderer.round_sample_count(spp)?;
            if let Some(w) = &count.warning {
                log(format!("warning: {w}"));
            }
            let n = count.count;
            renderer.set_sample_count(count)?;
            Some(n)
        }
        None => None,
    };
    if let Some(lost) = renderer.film_overridden(&scene.film) {
        log(format!(
            "warning: '{}' does not render this film's {lost}",
            renderer.integrator().name()
        ));
    }
    Ok(end)
}

/// Renders one step of `acc` of at most `budget` paths; returns the next step's
/// budget: towards a frame's time, at most doubling or halving per frame.
fn step(
    renderer: &mut Renderer,
    acc: &mut Accumulation,
    budget: u32,
    report: &mut ViewReport,
) -> Result<u32> {
    let t = Instant::now();
    let n = renderer.step(&mut acc.progress, budget)?;
    let dt = t.elapsed().as_secs_f64();
    acc.paths += n;
    report.samples += n;
    let mut next = budget;
    if n > 0 && dt > 0.0 {
        let ideal = n as f64 * FRAME_SECONDS / dt;
        next = ideal
            .clamp(n as f64 * 0.5, n as f64 * 2.0)
            .clamp(MIN_STEP_PATHS as f64, renderer.capacity() as f64) as u32;
    }
    if acc.progress.finished() {
        acc.finished = Some(acc.started.elapsed().as_secs_f64());
    }
    Ok(next)
}
