//! `wavetrace view` in a real window: under Xvfb (a virtual X server started per test
//! on a free display number) on whatever Vulkan device the tests use (lavapipe on
//! CI), with real key presses sent by xdotool (XTEST, to the focused window).
//!
//! What the window shows is read back with xwd.
//!
//! Without Xvfb, xdotool or xwd these tests skip with a loud message, unless
//! WAVETRACE_REQUIRE_XVFB is set (as `.ci/run` sets it): then they fail.
//! The tests that need no display (the no-display error) always run.

#![cfg(feature = "viewer")]

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use common::{repo, temp_dir};

/// The shipped Cornell box, small: 48x48 pixels keeps each test a few seconds on
/// lavapipe while leaving the walls, light and boxes several pixels wide.
const SCENE: &str = "scenes/cbox/cbox_path.xml";
const RES: &str = "res=48";

/// An X server of its own for one test, stopped when dropped.
struct Xvfb {
    child: Child,
    display: String,
}

/// Held while an Xvfb of this process starts or stops. A server killed outright
/// leaves its lock file (/tmp/.XN-lock) and socket behind, and two servers starting at
/// once could both find the lock stale, both remove it (the second removing the first's
/// new one) and both take display N. Servers here start one at a time and stop cleanly
/// (SIGTERM: Xvfb removes its lock file and socket).
static XVFB_START_STOP: Mutex<()> = Mutex::new(());

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _guard = XVFB_START_STOP.lock().unwrap_or_else(|e| e.into_inner());
        let _ = Command::new("sh")
            .args(["-c", &format!("kill -TERM {}", self.child.id())])
            .status();
        let deadline = Instant::now() + Duration::from_secs(5);
        while Instant::now() < deadline {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn have(tool: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Starts Xvfb on a free display, or says why not: `None` means skip (with a message
/// printed), and a missing Xvfb fails the test when WAVETRACE_REQUIRE_XVFB is set.
fn xvfb(test: &str) -> Option<Xvfb> {
    let missing: Vec<&str> = ["Xvfb", "xdotool", "xwd"]
        .into_iter()
        .filter(|t| !have(t))
        .collect();
    if !missing.is_empty() {
        let message = format!(
            "{test}: {} not installed (tools/setup.sh installs them)",
            missing.join(" and ")
        );
        if std::env::var_os("WAVETRACE_REQUIRE_XVFB").is_some() {
            panic!("{message}; WAVETRACE_REQUIRE_XVFB is set, so this is a failure");
        }
        eprintln!("\n*** SKIPPED {message} ***\n");
        return None;
    }
    // A server that reported its display but takes no client is replaced: up to three
    // tries. (The viewer's "no display" failures once blamed on such a server were the
    // reset that -noreset below prevents.)
    let mut why = String::new();
    for _ in 0..3 {
        match start_xvfb() {
            Ok(x) => return Some(x),
            Err(e) => why = e,
        }
    }
    panic!("{test}: {why}");
}

/// One Xvfb, once it reported its display and a client (xdotool) connected to it.
fn start_xvfb() -> Result<Xvfb, String> {
    // A display of our own, picked by Xvfb itself: with -displayfd it takes the first
    // number whose lock file it can create (atomic, so parallel tests never share one)
    // and writes that number to the given descriptor once it accepts connections.
    // (Choosing numbers here raced: two tests could start an Xvfb on one number, and
    // the loser then used the winner's server, which went away with the other test.)
    let guard = XVFB_START_STOP.lock().unwrap_or_else(|e| e.into_inner());
    let mut child = Command::new("Xvfb")
        .args([
            "-displayfd",
            "1",
            "-screen",
            "0",
            "640x480x24",
            "-nolisten",
            "tcp",
            // Without it the server resets when its last client leaves (the xdotool
            // check below), and a viewer connecting during the reset failed to open
            // the display.
            "-noreset",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start Xvfb");
    let stdout = child.stdout.take().expect("Xvfb's stdout");
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        use std::io::BufRead;
        let mut line = String::new();
        let _ = std::io::BufReader::new(stdout).read_line(&mut line);
        let _ = tx.send(line);
    });
    let x = match rx.recv_timeout(Duration::from_secs(20)) {
        Ok(line) if line.trim().parse::<u32>().is_ok() => Xvfb {
            child,
            display: format!(":{}", line.trim()),
        },
        other => {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("Xvfb did not report a display ({other:?})"));
        }
    };
    let connects = Command::new("xdotool")
        .arg("getdisplaygeometry")
        .env("DISPLAY", &x.display)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    // Before `x` may drop (its Drop takes the lock).
    drop(guard);
    if connects {
        Ok(x)
    } else {
        Err(format!(
            "no client could connect to Xvfb's display {}",
            x.display
        ))
    }
}

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_wavetrace")
}

/// `wavetrace render` of the scene at `spp` to `dir/render.exr` (and `.png`).
fn render_png(dir: &Path, spp: u32) -> PathBuf {
    let out = dir.join("render.exr");
    let status = Command::new(bin())
        .current_dir(repo(""))
        .args(["render", SCENE, "-D", RES, "--seed", "3", "-q"])
        .args(["--spp", &spp.to_string(), "-o"])
        .arg(&out)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run wavetrace render");
    assert!(
        status.status.success(),
        "render failed: {}",
        String::from_utf8_lossy(&status.stderr)
    );
    dir.join("render.png")
}

fn rgb8(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()))
        .to_rgb8()
}

/// The most two 8-bit images differ by in any channel of any pixel.
fn max_level_difference(a: &image::RgbImage, b: &image::RgbImage) -> u8 {
    assert_eq!(a.dimensions(), b.dimensions(), "image sizes");
    a.as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0)
}

/// An sRGB code back to linear (IEC 61966-2-1).
fn linear(code: u8) -> f64 {
    let v = code as f64 / 255.0;
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// A `wavetrace view` running on an X display, stopped when dropped.
struct Viewer {
    child: Child,
    display: String,
    window: String,
    /// How much slower than the machine the waits were set on this one is: the
    /// viewer's start-up (kernels compiled and a first frame shown) over 10 s, at
    /// least 1. Every wait below is its stated seconds times this, so a slow or loaded
    /// machine gets longer waits instead of a false failure.
    slowness: f64,
}

impl Viewer {
    /// Starts the viewer with `args` in `dir` and waits for its window.
    fn start(x: &Xvfb, dir: &Path, args: &[&str]) -> Viewer {
        let scene = repo(SCENE);
        let child = Command::new(bin())
            .current_dir(dir)
            .arg("view")
            .arg(&scene)
            .args(["-D", RES, "--seed", "3"])
            .args(args)
            .env("DISPLAY", &x.display)
            .env_remove("WAYLAND_DISPLAY")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start wavetrace view");
        let mut viewer = Viewer {
            child,
            display: x.display.clone(),
            window: String::new(),
            slowness: 1.0,
        };
        // Lavapipe compiles the kernels at their first dispatch: allow for a cold
        // shader cache.
        let started = Instant::now();
        let deadline = started + Duration::from_secs(180);
        while Instant::now() < deadline {
            viewer.assert_running();
            let out = viewer.xdotool(&["search", "--name", "^wavetrace"]);
            if let Some(id) = out.lines().next().filter(|l| !l.trim().is_empty()) {
                viewer.window = id.trim().to_string();
                viewer.slowness = (started.elapsed().as_secs_f64() / 10.0).max(1.0);
                return viewer;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        panic!("the viewer's window did not appear");
    }

    fn xdotool(&self, args: &[&str]) -> String {
        let out = Command::new("xdotool")
            .args(args)
            .env("DISPLAY", &self.display)
            .output()
            .expect("run xdotool");
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    fn assert_running(&mut self) {
        if let Ok(Some(status)) = self.child.try_wait() {
            let mut err = String::new();
            if let Some(mut e) = self.child.stderr.take() {
                use std::io::Read;
                let _ = e.read_to_string(&mut err);
            }
            panic!("the viewer exited ({status}):\n{err}");
        }
    }

    /// The instant `seconds` from now, scaled by this machine's slowness.
    fn deadline(&self, seconds: u64) -> Instant {
        Instant::now() + Duration::from_secs_f64(seconds as f64 * self.slowness)
    }

    fn title(&self) -> String {
        self.xdotool(&["getwindowname", &self.window])
    }

    /// Waits until the title contains `needle` (the viewer still running).
    fn wait_title(&mut self, needle: &str, seconds: u64) -> String {
        let deadline = self.deadline(seconds);
        loop {
            self.assert_running();
            let t = self.title();
            if t.contains(needle) {
                return t;
            }
            assert!(
                Instant::now() < deadline,
                "the title never showed {needle:?}; last: {t:?}"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Presses `key` in the window, as a person at the keyboard would (focus, then
    /// XTEST key events).
    fn key(&self, key: &str) {
        self.xdotool(&["windowfocus", "--sync", &self.window]);
        self.xdotool(&["key", "--delay", "30", key]);
    }

    /// Waits for the process to end by itself; returns its status and stderr.
    fn wait_exit(mut self, seconds: u64) -> (i32, String) {
        let deadline = self.deadline(seconds);
        loop {
            if let Ok(Some(status)) = self.child.try_wait() {
                let mut err = String::new();
                if let Some(mut e) = self.child.stderr.take() {
                    use std::io::Read;
                    let _ = e.read_to_string(&mut err);
                }
                return (status.code().unwrap_or(-1), err);
            }
            assert!(Instant::now() < deadline, "the viewer did not exit");
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Waits for `path` to exist and be complete (its size stable).
fn wait_file(path: &Path, viewer: &mut Viewer) {
    let deadline = viewer.deadline(60);
    let mut last = None;
    loop {
        viewer.assert_running();
        let size = std::fs::metadata(path).map(|m| m.len()).ok();
        if size.is_some() && size == last {
            return;
        }
        last = size;
        assert!(
            Instant::now() < deadline,
            "{} was never written",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn screenshot_equals_the_render_of_the_same_samples() {
    let Some(x) = xvfb("screenshot") else { return };
    let dir = temp_dir("screenshot");
    let shot = dir.join("view.png");
    let out = Command::new(bin())
        .current_dir(repo(""))
        .args([
            "view",
            SCENE,
            "-D",
            RES,
            "--seed",
            "3",
            "--spp",
            "16",
            "--screenshot",
        ])
        .arg(&shot)
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run wavetrace view");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "view failed: {err}");
    assert!(err.contains("first frame"), "{err}");
    let view = rgb8(&shot);
    let render = rgb8(&render_png(&dir, 16));
    // The same samples in the same film, tone mapped by the GPU (GLSL pow) and by
    // the host (Rust powf): a code may round the other way, never more.
    let d = max_level_difference(&view, &render);
    assert!(d <= 1, "screenshot and render differ by {d} levels");
    let mean = view.as_raw().iter().map(|&v| v as f64).sum::<f64>() / view.as_raw().len() as f64;
    assert!(mean > 20.0, "the screenshot is nearly black (mean {mean})");
}

#[test]
fn keys_resize_and_escape() {
    let Some(x) = xvfb("keys") else { return };
    let dir = temp_dir("keys");
    let mut v = Viewer::start(&x, &dir, &["--spp", "4"]);
    // Resizing while it renders: the swapchain is made again, the film goes on.
    v.xdotool(&["windowsize", "--sync", &v.window.clone(), "200", "120"]);
    v.wait_title("4/4 spp, done", 120);
    v.xdotool(&["windowsize", "--sync", &v.window.clone(), "90", "150"]);
    v.key("p");
    let first = dir.join("cbox_path-4spp.png");
    wait_file(&first, &mut v);
    wait_file(&dir.join("cbox_path-4spp.exr"), &mut v);
    // What was saved is the render of those 4 samples (resizing changed nothing).
    let saved = rgb8(&first);
    let render = rgb8(&render_png(&dir, 4));
    let d = max_level_difference(&saved, &render);
    assert!(
        d <= 1,
        "the saved image differs from the render by {d} levels"
    );

    // Exposure: two presses of ] are one stop, twice the linear value; the film
    // (and so the EXR) does not change.
    v.key("bracketright");
    v.key("bracketright");
    v.wait_title("exposure +1.0", 20);
    v.key("p");
    let second = dir.join("cbox_path-4spp-2.png");
    wait_file(&second, &mut v);
    let brighter = rgb8(&second);
    let (mut ratio_sum, mut n) = (0.0, 0);
    for (a, b) in saved.as_raw().iter().zip(brighter.as_raw()) {
        // Where neither is near the 8-bit steps' coarse end nor clipped.
        if (40..=170).contains(a) && *b < 250 {
            ratio_sum += linear(*b) / linear(*a);
            n += 1;
        }
    }
    assert!(n > 100, "too few comparable pixels ({n})");
    let ratio = ratio_sum / n as f64;
    // 8-bit rounding moves each ratio by under 2% at these codes; the mean of many
    // is within 1% of 2 unless the exposure is wrong.
    assert!((ratio - 2.0).abs() < 0.02, "one stop brightened by {ratio}");
    let exr_a = wavetrace::image::Image::read_exr(dir.join("cbox_path-4spp.exr")).expect("exr");
    let exr_b = wavetrace::image::Image::read_exr(dir.join("cbox_path-4spp-2.exr")).expect("exr");
    assert_eq!(exr_a, exr_b, "exposure changed the film");

    v.key("Escape");
    let (code, err) = v.wait_exit(30);
    assert_eq!(code, 0, "Esc should quit cleanly: {err}");
    assert!(err.contains("saved"), "{err}");
}

/// On the newer lavapipe at 512 bits, which a machine's driver record (`wavetrace
/// driver --calibrate`) may choose, the window shows its frames and the screenshot is
/// the render's: the window once used the driver's blit, whose fragment shader
/// llvmpipe at 512 bits crashed compiling.
#[test]
fn the_viewer_runs_on_a_recorded_newer_lavapipe_at_512_bits() {
    let Some(driver) = common::installed_prebuilt() else {
        return;
    };
    let Some(x) = xvfb("wide") else { return };
    let dir = temp_dir("wide");
    let cache = dir.join("cache");
    let machine = wavetrace::gpu::driver_choice::machine();
    common::write_driver_record(&cache, &machine, Some(&driver), 512);
    let shot = dir.join("view.png");
    let out = Command::new(bin())
        .current_dir(repo(""))
        .args(["view", SCENE, "-D", RES, "--seed", "3", "--spp", "4"])
        .arg("--screenshot")
        .arg(&shot)
        .env("DISPLAY", &x.display)
        .env("XDG_CACHE_HOME", &cache)
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAVETRACE_DRIVER")
        .env_remove("WAVETRACE_DRIVER_CHOSEN")
        .env_remove("LP_NATIVE_VECTOR_WIDTH")
        .env_remove("VK_ICD_FILENAMES")
        .env_remove("VK_DRIVER_FILES")
        .output()
        .expect("run wavetrace view");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "view failed ({}): {err}", out.status);
    assert!(err.contains("512 bits"), "{err}");
    assert!(err.contains("first frame"), "{err}");
    let d = max_level_difference(&rgb8(&shot), &rgb8(&render_png(&dir, 4)));
    assert!(
        d <= 1,
        "the 512-bit screenshot and the render differ by {d} levels"
    );
}

/// What X window `id` on `display` shows, read with xwd (its XWD dump: a header of
/// big-endian 32-bit fields, colour map entries, then rows of pixels).
fn window_pixels(display: &str, id: &str) -> image::RgbImage {
    let out = Command::new("xwd")
        .args(["-silent", "-id", id])
        .env("DISPLAY", display)
        .output()
        .expect("run xwd");
    assert!(
        out.status.success(),
        "xwd failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let d = out.stdout;
    let field = |i: usize| u32::from_be_bytes(d[4 * i..4 * i + 4].try_into().unwrap());
    let (header, format, width, height) = (field(0), field(2), field(4), field(5));
    let (byte_order, bits, bytes_per_line) = (field(7), field(11), field(12));
    let masks = [field(14), field(15), field(16)];
    let colors = field(19);
    assert_eq!(format, 2, "xwd: not a ZPixmap");
    assert_eq!(bits, 32, "xwd: {bits} bits a pixel");
    let start = (header + colors * 12) as usize;
    image::RgbImage::from_fn(width, height, |x, y| {
        let at = start + (y * bytes_per_line + 4 * x) as usize;
        let b: [u8; 4] = d[at..at + 4].try_into().unwrap();
        let v = if byte_order == 0 {
            u32::from_le_bytes(b)
        } else {
            u32::from_be_bytes(b)
        };
        image::Rgb(masks.map(|m| ((v & m) >> m.trailing_zeros()) as u8))
    })
}

#[test]
fn the_window_shows_the_picture_letterboxed() {
    use wavetrace::gpu::letterbox::{self, WindowFormat};

    let Some(x) = xvfb("window") else { return };
    let dir = temp_dir("window");
    let mut v = Viewer::start(&x, &dir, &["--spp", "4"]);
    v.xdotool(&["windowsize", "--sync", &v.window.clone(), "200", "120"]);
    v.wait_title("4/4 spp, done", 120);

    // What the window should show: the render of the same samples (which the viewer's
    // picture equals within a level, see above) put in its letterbox by the kernel.
    let render = rgb8(&render_png(&dir, 4));
    let (pw, ph) = render.dimensions();
    let pixels: Vec<u32> = render
        .pixels()
        .map(|p| u32::from_le_bytes([p[0], p[1], p[2], 255]))
        .collect();
    let format = WindowFormat {
        bgra: false,
        srgb: false,
    };
    let push = letterbox::push((200, 120), (pw, ph), format);
    // 48x48 scaled 2.5 times, bars of 40 pixels left and right.
    assert_eq!((push.x, push.y, push.width, push.height), (40, 0, 120, 120));
    let drawn = common::letterbox_window(&push, &pixels);
    let want = image::RgbImage::from_fn(200, 120, |x, y| {
        let [r, g, b, _] = drawn[(y * 200 + x) as usize].to_le_bytes();
        image::Rgb([r, g, b])
    });

    // The frame after the resize may still be on its way: read until it is there.
    let deadline = v.deadline(30);
    loop {
        v.assert_running();
        let shown = window_pixels(&x.display, &v.window);
        let d = (shown.dimensions() == (200, 120)).then(|| max_level_difference(&shown, &want));
        if d.is_some_and(|d| d <= 1) {
            // The bars: grey 0.05, code 13, on both sides.
            assert_eq!(shown.get_pixel(0, 60), &image::Rgb([13, 13, 13]));
            assert_eq!(shown.get_pixel(199, 0), &image::Rgb([13, 13, 13]));
            break;
        }
        assert!(
            Instant::now() < deadline,
            "the window ({:?}) never showed the letterboxed render (largest difference {d:?} levels)",
            shown.dimensions()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    v.key("Escape");
    let (code, err) = v.wait_exit(30);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn a_camera_key_moves_the_image_and_restarts_the_samples() {
    let Some(x) = xvfb("camera") else { return };
    let dir = temp_dir("camera");
    // No --spp: it accumulates until closed.
    let mut v = Viewer::start(&x, &dir, &[]);
    // Samples per pixel in the title (0 before the first frame names any).
    let spp_of = |title: &str| -> u32 {
        if !title.contains(" spp") {
            return 0;
        }
        title
            .split(" spp")
            .next()
            .and_then(|s| s.rsplit("| ").next())
            .and_then(|s| s.trim().parse().ok())
            .unwrap_or_else(|| panic!("no spp in the title {title:?}"))
    };
    let deadline = v.deadline(120);
    while spp_of(&v.title()) < 4 {
        v.assert_running();
        assert!(Instant::now() < deadline, "the viewer never reached 4 spp");
        std::thread::sleep(Duration::from_millis(50));
    }
    v.key("p");
    let before = dir
        .read_dir()
        .expect("dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|e| e == "exr"));
    let deadline = v.deadline(30);
    let mut before = before;
    while before.is_none() {
        assert!(Instant::now() < deadline, "P saved nothing");
        std::thread::sleep(Duration::from_millis(100));
        before = dir
            .read_dir()
            .expect("dir")
            .filter_map(|e| e.ok().map(|e| e.path()))
            .find(|p| p.extension().is_some_and(|e| e == "exr"));
    }
    let before = before.expect("saved exr");
    wait_file(&before, &mut v);
    // Turn left by 10 presses of 2 degrees: the accumulation starts again from 0
    // (the title shows it at once) ...
    for _ in 0..10 {
        v.key("Left");
    }
    v.wait_title("| 0 spp", 20);
    let deadline = v.deadline(120);
    while spp_of(&v.title()) < 4 {
        v.assert_running();
        assert!(
            Instant::now() < deadline,
            "the viewer never got back to 4 spp"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    v.key("p");
    // ... and the image moved: block means (8x8 pixels, so a few samples' noise
    // averages out) differ much more than noise could make them.
    let deadline = v.deadline(30);
    let after = loop {
        let found = dir
            .read_dir()
            .expect("dir")
            .filter_map(|e| e.ok().map(|e| e.path()))
            .find(|p| p.extension().is_some_and(|e| e == "exr") && *p != before);
        if let Some(p) = found {
            break p;
        }
        assert!(Instant::now() < deadline, "the second P saved nothing");
        std::thread::sleep(Duration::from_millis(100));
    };
    wait_file(&after, &mut v);
    let a = wavetrace::image::Image::read_exr(&before).expect("exr");
    let b = wavetrace::image::Image::read_exr(&after).expect("exr");
    let blocks = |img: &wavetrace::image::Image| -> Vec<f64> {
        let mut out = Vec::new();
        for by in 0..img.height / 8 {
            for bx in 0..img.width / 8 {
                let mut s = 0.0;
                for y in 0..8 {
                    for x in 0..8 {
                        let p = img.pixel(bx * 8 + x, by * 8 + y);
                        s += (p[0] + p[1] + p[2]) as f64 / 3.0;
                    }
                }
                out.push(s / 64.0);
            }
        }
        out
    };
    let (ba, bb) = (blocks(&a), blocks(&b));
    let mean = ba.iter().sum::<f64>() / ba.len() as f64;
    let diff = ba.iter().zip(&bb).map(|(x, y)| (x - y).abs()).sum::<f64>() / ba.len() as f64;
    // A 20-degree turn of a 39-degree view shifts every wall by half the image.
    assert!(
        diff > 0.2 * mean,
        "the image barely changed: mean block difference {diff} for mean {mean}"
    );
    v.key("Escape");
    let (code, err) = v.wait_exit(30);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn no_display_is_a_clear_error() {
    let out = Command::new(bin())
        .current_dir(repo(""))
        .args(["view", SCENE, "-D", RES])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run wavetrace view");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for needle in ["no display", "wavetrace render", "--tev"] {
        assert!(err.contains(needle), "stderr lacks {needle:?}: {err}");
    }
}

#[test]
fn an_unreachable_display_is_a_clear_error() {
    // A display number no server listens on: GLFW cannot connect.
    let out = Command::new(bin())
        .current_dir(repo(""))
        .args(["view", SCENE, "-D", RES])
        .env("DISPLAY", ":987")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run wavetrace view");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("no display"), "{err}");
    assert!(err.contains("--tev"), "{err}");
}

/// The Cornell box with a second camera (sensor 1), beside it in `dir`.
fn two_sensor_scene(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(repo(SCENE)).expect("the scene");
    let first = &text[text.find("    <sensor").expect("a sensor")..];
    let first = &first[..first.find("</sensor>").expect("its end") + "</sensor>\n".len()];
    let second = first.replace("origin=\"278, 273, -800\"", "origin=\"150, 300, -700\"");
    assert_ne!(first, second);
    let at = text.find(first).unwrap() + first.len();
    let scene = format!(
        "{}    <path value=\"{}\"/>\n{second}{}",
        &text[..at],
        repo("scenes/cbox").display(),
        &text[at..]
    );
    let path = dir.join("two.xml");
    std::fs::write(&path, scene).expect("write the scene");
    path
}

/// `view --sensor 1` shows the second camera: its screenshot is `render --sensor 1` of
/// the same samples; an index out of range is an error naming the scene and how many
/// sensors it has.
#[test]
fn view_picks_a_sensor() {
    let Some(x) = xvfb("sensor") else { return };
    let dir = temp_dir("view_sensor");
    let scene = two_sensor_scene(&dir);
    let shot = dir.join("view.png");
    let view = |sensor: &str, shot: &Path| {
        Command::new(bin())
            .current_dir(&dir)
            .arg("view")
            .arg(&scene)
            .args(["-D", RES, "--seed", "3", "--spp", "4", "--sensor", sensor])
            .arg("--screenshot")
            .arg(shot)
            .env("DISPLAY", &x.display)
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .expect("run wavetrace view")
    };
    let out = view("1", &shot);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "view failed: {err}");
    let render = dir.join("render.exr");
    let status = Command::new(bin())
        .arg("render")
        .arg(&scene)
        .args([
            "-D", RES, "--seed", "3", "-q", "--spp", "4", "--sensor", "1", "-o",
        ])
        .arg(&render)
        .env_remove("DISPLAY")
        .output()
        .expect("run wavetrace render");
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let (view_img, render_img) = (rgb8(&shot), rgb8(&dir.join("render.png")));
    let d = max_level_difference(&view_img, &render_img);
    assert!(
        d <= 1,
        "screenshot and render of sensor 1 differ by {d} levels"
    );
    let first = rgb8(&render_png(&dir, 4));
    assert!(
        max_level_difference(&view_img, &first) > 10,
        "sensor 1 shows what sensor 0 shows"
    );
    let out = view("2", &dir.join("none.png"));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("two.xml") && err.contains("the scene has 2 sensors (0 to 1)"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
