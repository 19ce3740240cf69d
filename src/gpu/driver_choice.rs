//! Which CPU Vulkan driver, at which vector width, a command-line run uses.
//!
//! Debian 12's lavapipe (Mesa 22.3) runs 8 lanes of 32 bits; on an AVX-512 host a newer
//! one (Mesa 26, installed by `tools/lavapipe.sh --prebuilt` under its own loader and
//! libraries) runs 16 with `LP_NATIVE_VECTOR_WIDTH=512`, which the 512-bit abort's
//! workaround made correct (docs/performance.md). Which is fastest depends on the
//! machine, so `wavetrace driver --calibrate` renders the same small image under every
//! candidate (Debian's driver; each installed newer one at 256 and 512 bits), keeps
//! only those whose image equals Debian's driver's within float rounding, and records
//! the fastest in `~/.cache/wavetrace/driver-choice.json` with the machine it was
//! measured on (CPU model and vector extensions). Every later run on that machine
//! starts itself again under the recorded driver and width ([`apply`]) before it
//! opens Vulkan, without the user setting anything; `render` names the choice in its
//! device line. Debian's driver stays the fallback: no record, a record of another
//! machine, a driver folder gone, or a failed re-exec all run on it.
//!
//! Not applied where the user chose for themselves (`VK_ICD_FILENAMES`,
//! `VK_DRIVER_FILES` or `LP_NATIVE_VECTOR_WIDTH` set) or `WAVETRACE_DRIVER=system`.
//! Library users (and the Python package) open whatever driver their process has: the
//! newer driver needs its own C library, which only a fresh process can load.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use serde_json::{json, Value};

/// Set in the process [`apply`] starts again: the choice, for the device line (and so
/// that process does not start itself once more).
pub const CHOSEN_ENV: &str = "WAVETRACE_DRIVER_CHOSEN";
/// `system`: Debian's driver at its default width, whatever the record says.
pub const DRIVER_ENV: &str = "WAVETRACE_DRIVER";
const RECORD: &str = "driver-choice.json";

/// One driver and width a run can use.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    /// A newer lavapipe's folder (`lavapipe-deb-<version>` with `bin/with-lavapipe`,
    /// `lvp_icd.json` and `root/`); `None`: the system's driver.
    pub driver: Option<PathBuf>,
    /// `LP_NATIVE_VECTOR_WIDTH`; `None`: the driver's default.
    pub width: Option<u32>,
}

impl Candidate {
    pub fn describe(&self) -> String {
        let driver = match &self.driver {
            None => "the system's driver".to_string(),
            Some(d) => d
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| d.display().to_string()),
        };
        match self.width {
            Some(w) => format!("{driver} at {w} bits"),
            None => format!("{driver} at its default width"),
        }
    }

    /// The command that runs `exe` under this candidate (without [`CHOSEN_ENV`]).
    fn command(&self, exe: &Path) -> Command {
        let mut cmd = match &self.driver {
            None => Command::new(exe),
            Some(d) => {
                let lib = d.join("root/usr/lib/x86_64-linux-gnu");
                let mut c = Command::new(lib.join("ld-linux-x86-64.so.2"));
                c.arg("--library-path").arg(&lib).arg(exe);
                c.env("VK_ICD_FILENAMES", d.join("lvp_icd.json"));
                c
            }
        };
        if let Some(w) = self.width {
            cmd.env("LP_NATIVE_VECTOR_WIDTH", w.to_string());
        }
        cmd
    }

    fn to_json(&self) -> Value {
        json!({ "driver": self.driver.as_ref().map(|d| d.display().to_string()), "width": self.width })
    }

    fn from_json(v: &Value) -> Option<Candidate> {
        Some(Candidate {
            driver: match v.get("driver")? {
                Value::Null => None,
                d => Some(PathBuf::from(d.as_str()?)),
            },
            width: match v.get("width")? {
                Value::Null => None,
                w => Some(u32::try_from(w.as_u64()?).ok()?),
            },
        })
    }

    /// Whether this candidate can run here: a newer driver's folder still complete.
    fn available(&self) -> bool {
        self.driver.as_ref().is_none_or(|d| {
            d.join(".complete").is_file()
                && d.join("lvp_icd.json").is_file()
                && d.join("root/usr/lib/x86_64-linux-gnu/ld-linux-x86-64.so.2")
                    .exists()
        })
    }
}

/// The machine a record was measured on: the CPU's model and the vector extensions
/// that decide how wide llvmpipe can run.
pub fn machine() -> String {
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let field = |name: &str| {
        cpuinfo
            .lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_once(':'))
            .map(|(_, v)| v.trim().to_string())
            .unwrap_or_default()
    };
    let flags = field("flags");
    let wide: Vec<&str> = ["avx2", "fma", "avx512f", "avx512bw", "avx512vl"]
        .into_iter()
        .filter(|f| flags.split_whitespace().any(|x| x == *f))
        .collect();
    format!("{} [{}]", field("model name"), wide.join(" "))
}

fn record_path() -> Option<PathBuf> {
    super::device::cache_dir().map(|d| d.join(RECORD))
}

/// The newer lavapipe folders installed in the cache (`tools/lavapipe.sh --prebuilt`).
pub fn installed_drivers() -> Vec<PathBuf> {
    let Some(dir) = super::device::cache_dir() else {
        return Vec::new();
    };
    let mut found: Vec<PathBuf> = std::fs::read_dir(&dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("lavapipe-deb-"))
        })
        .collect();
    found.sort();
    found.retain(|d| {
        Candidate {
            driver: Some(d.clone()),
            width: None,
        }
        .available()
    });
    found
}

/// The recorded choice for this machine, if there is one and it can still run.
pub fn recorded() -> Option<Candidate> {
    let text = std::fs::read_to_string(record_path()?).ok()?;
    let v: Value = serde_json::from_str(&text).ok()?;
    if v.get("machine")?.as_str()? != machine() {
        return None;
    }
    let c = Candidate::from_json(v.get("choice")?)?;
    c.available().then_some(c)
}

fn user_chose() -> bool {
    [
        "VK_ICD_FILENAMES",
        "VK_DRIVER_FILES",
        "LP_NATIVE_VECTOR_WIDTH",
    ]
    .iter()
    .any(|v| std::env::var_os(v).is_some())
        || std::env::var(DRIVER_ENV).is_ok_and(|v| v == "system")
}

/// Starts this process again under the recorded driver and width, unless it already
/// runs under them, the user chose a driver, or there is nothing (or the system's
/// default) recorded. Returns only when this process goes on as it is; a failed
/// re-exec says why and goes on on the system's driver.
pub fn apply() {
    if std::env::var_os(CHOSEN_ENV).is_some() || user_chose() {
        return;
    }
    let Some(choice) = recorded() else {
        return;
    };
    if choice.driver.is_none() && choice.width.is_none() {
        return;
    }
    let Ok(exe) = std::env::current_exe() else {
        return;
    };
    let mut cmd = choice.command(&exe);
    cmd.args(std::env::args_os().skip(1));
    cmd.env(CHOSEN_ENV, choice.describe());
    use std::os::unix::process::CommandExt;
    let e = cmd.exec();
    eprintln!(
        "warning: could not start under {} ({e}); running on the system's driver",
        choice.describe()
    );
}

/// What the device line adds: the driver this process runs under, if [`apply`] chose it.
pub fn chosen_note() -> Option<String> {
    std::env::var(CHOSEN_ENV).ok().map(|c| {
        format!("{c}, chosen for this machine by `wavetrace driver --calibrate` (WAVETRACE_DRIVER=system: Debian's)")
    })
}

/// Every candidate: the system's driver, and each installed newer one at 256 and 512
/// bits.
pub fn candidates() -> Vec<Candidate> {
    let mut c = vec![Candidate {
        driver: None,
        width: None,
    }];
    for d in installed_drivers() {
        for w in [256, 512] {
            c.push(Candidate {
                driver: Some(d.clone()),
                width: Some(w),
            });
        }
    }
    c
}

/// Renders `scene` (with `args`) under each candidate, `runs` times, keeps the
/// candidates whose image equals the system driver's within float rounding, records
/// the fastest (by its best run) and returns the table (candidate, seconds or why
/// not).
pub fn calibrate(scene: &Path, args: &[String], runs: u32) -> Result<Vec<(Candidate, String)>> {
    let exe = std::env::current_exe().context("finding wavetrace's own executable")?;
    let dir = tempfile_dir()?;
    let mut table = Vec::new();
    let mut reference: Option<crate::image::Image> = None;
    let mut best: Option<(Candidate, f64)> = None;
    for (i, c) in candidates().into_iter().enumerate() {
        let out = dir.join(format!("candidate{i}.exr"));
        let mut seconds = f64::INFINITY;
        let mut failure = None;
        for _ in 0..runs.max(1) {
            let mut cmd = c.command(&exe);
            cmd.arg("render")
                .arg(scene)
                .args(args)
                .arg("-o")
                .arg(&out)
                .arg("--quiet")
                .env(DRIVER_ENV, "system")
                .env_remove(CHOSEN_ENV);
            let t = Instant::now();
            match cmd.output() {
                Ok(o) if o.status.success() => seconds = seconds.min(t.elapsed().as_secs_f64()),
                Ok(o) => {
                    let err = String::from_utf8_lossy(&o.stderr);
                    failure = Some(format!(
                        "failed ({}): {}",
                        o.status,
                        err.lines().last().unwrap_or("")
                    ));
                    break;
                }
                Err(e) => {
                    failure = Some(format!("could not start: {e}"));
                    break;
                }
            }
        }
        if let Some(f) = failure {
            table.push((c, f));
            continue;
        }
        let img = crate::image::Image::read_exr(&out)
            .with_context(|| format!("reading the render of {}", c.describe()))?;
        match &reference {
            None => reference = Some(img),
            Some(r) => {
                let d = largest_relative_difference(r, &img);
                if d > 1e-3 {
                    table.push((
                        c,
                        format!("renders another image (largest relative difference {d:.2e})"),
                    ));
                    continue;
                }
            }
        }
        table.push((c.clone(), format!("{seconds:.2} s")));
        if best.as_ref().is_none_or(|(_, b)| seconds < *b) {
            best = Some((c, seconds));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    let Some((choice, _)) = best else {
        bail!("no driver rendered the calibration scene");
    };
    let measured: Vec<Value> = table
        .iter()
        .map(|(c, r)| json!({ "candidate": c.to_json(), "result": r }))
        .collect();
    let record = json!({
        "machine": machine(),
        "choice": choice.to_json(),
        "scene": scene.display().to_string(),
        "args": args,
        "measured": measured,
    });
    let path = record_path().context("no cache folder (neither XDG_CACHE_HOME nor HOME set)")?;
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("creating {}", parent.display()))?;
    }
    std::fs::write(&path, serde_json::to_string_pretty(&record)? + "\n")
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(table)
}

/// The largest difference between two images' values relative to the larger of the
/// two (values under 1e-3 count as 1e-3); infinite for images of different sizes.
fn largest_relative_difference(a: &crate::image::Image, b: &crate::image::Image) -> f64 {
    if a.width != b.width || a.height != b.height || a.rgb.len() != b.rgb.len() {
        return f64::INFINITY;
    }
    a.rgb
        .iter()
        .zip(&b.rgb)
        .map(|(&x, &y)| {
            let (x, y) = (x as f64, y as f64);
            (x - y).abs() / x.abs().max(y.abs()).max(1e-3)
        })
        .fold(0.0, f64::max)
}

fn tempfile_dir() -> Result<PathBuf> {
    let dir = std::env::temp_dir().join(format!("wavetrace-calibrate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    Ok(dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn candidates_survive_their_record() {
        for c in [
            Candidate {
                driver: None,
                width: None,
            },
            Candidate {
                driver: Some(PathBuf::from("/x/lavapipe-deb-26.2.6-1")),
                width: Some(512),
            },
        ] {
            assert_eq!(Candidate::from_json(&c.to_json()), Some(c));
        }
        assert_eq!(
            Candidate::from_json(&json!({ "driver": 3, "width": 512 })),
            None
        );
    }

    #[test]
    fn the_machine_names_its_cpu_and_vector_extensions() {
        let m = machine();
        assert!(m.contains('[') && m.ends_with(']'), "{m}");
    }
}
