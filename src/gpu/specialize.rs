//! Specialized SPIR-V: a kernel's specialization constants written into its module and
//! the code they switch off removed before the driver sees it, cached on disk.
//!
//! Why: lavapipe (Mesa 22.3) translates SPIR-V to NIR and optimizes it inside
//! `vkCreateComputePipelines`, and it inlines every function before it drops the
//! branches that specialization disables; none of that work is kept (its pipeline
//! cache is a stub, and Mesa's disk cache holds only the LLVM code built at the first
//! dispatch). `shade` carries every integrator, BSDF, emitter and medium, so every run
//! paid about 1 s of CPU creating it even for the Cornell box's `ao`. Measured on the
//! Cornell box (`ao`, one process, CPU time): `shade` from 352 KB of SPIR-V took 3 s of
//! CPU on a loaded machine, from its 53 KB specialized form 30 ms.
//!
//! The work is done by `spirv-opt` (SPIRV-Tools; Debian's `spirv-tools`, which
//! `glslang-tools` depends on): the constants' values are written into the module
//! here, then its passes turn them into plain constants (`--freeze-spec-const`), fold
//! the expressions of them (`--fold-spec-const-op-composite`), replace branches on
//! constants by the branch taken (`--eliminate-dead-branches`) and delete the
//! functions and instructions left unused. None of these passes changes arithmetic.
//! The result depends only on the module and the constants, so it is kept in
//! `~/.cache/wavetrace/spirv/` (`$XDG_CACHE_HOME/wavetrace/spirv/`) and a later run
//! reads it back instead of running `spirv-opt`.
//!
//! Where `spirv-opt` cannot be run (not installed, or it fails), the kernel is made as
//! before, from the whole module with the driver applying the constants: the same
//! kernel, created more slowly. `WAVETRACE_SPECIALIZE=driver` asks for that path
//! always (to compare, or to work around a faulty `spirv-opt`); `WAVETRACE_SPIRV_OPT`
//! names the `spirv-opt` to run.

use std::hash::{Hash, Hasher};
use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Mutex;

use super::error::Error;

/// SPIR-V's magic number, the first word of every module.
const MAGIC: u32 = 0x0723_0203;
/// Opcodes and the decoration this file reads (SPIR-V 1.6 specification, 3.32 and 3.20).
const OP_DECORATE: u32 = 71;
const OP_SPEC_CONSTANT_TRUE: u32 = 48;
const OP_SPEC_CONSTANT_FALSE: u32 = 49;
const OP_SPEC_CONSTANT: u32 = 50;
const DECORATION_SPEC_ID: u32 = 1;

/// The passes run, in order. Part of the cache key: changing them invalidates entries.
const PASSES: &[&str] = &[
    "--skip-validation",
    "--freeze-spec-const",
    "--fold-spec-const-op-composite",
    "--eliminate-dead-branches",
    "--eliminate-dead-functions",
    "--eliminate-dead-code-aggressive",
    "--eliminate-dead-functions",
];

/// Passes run after [`PASSES`] for kernels made with `inline` ([`specialize`]): every
/// function inlined into the entry point (merge-return first, which the inliner needs
/// for functions with early returns), its variables turned into SSA values, constants
/// propagated into the inlined code and the branches and code they switch off removed.
/// lavapipe then gets one function with no dead code, and creates the pipeline 4-6x
/// faster, since it inlines every call itself and optimizes the whole before dropping
/// what the arguments switch off (`shade` of the Cornell box: 300 -> 50-80 ms per
/// run). But merge-return turns a function with early returns into a loop around its
/// body, and where that function runs inside a loop llvmpipe pays for the loop's
/// bookkeeping, so the functions that run in loops return once, at their end: the
/// traversal's primitive tests, and the medium code's tracking and crossing loops
/// (medium.glsl; callgrind, media/cube.xml: shade +12%, shadow +15% inlined with
/// their early returns, +4% and +6% without them).
/// The arguments that are constants at a call (a primitive's kind in the traversal's
/// steps tested in turn, a traversal's mode) are propagated and the branches they
/// switch off removed once right after inlining, while the other variables are still
/// in memory, and again after the SSA rewrite: the media cube's `first_bounce` with its
/// 16 primitives tested in turn (four traversals, each step inlining every kind's test)
/// grew to 7 MB inlined and 12 MB in SSA form, past spirv-opt's limit of 4,194,303 ids
/// (it crashed, and the driver then specialized the kernel in 68 s); pruned before the
/// rewrite it takes 4.7 s and the other kernels 1.5-5x less time than before.
/// Like [`PASSES`], none of them changes arithmetic.
const INLINE_PASSES: &[&str] = &[
    "--merge-return",
    "--inline-entry-points-exhaustive",
    "--eliminate-dead-functions",
    "--private-to-local",
    "--eliminate-local-single-block",
    "--eliminate-local-single-store",
    "--ccp",
    "--eliminate-dead-branches",
    "--eliminate-dead-code-aggressive",
    "--convert-local-access-chains",
    "--ssa-rewrite",
    "--ccp",
    "--eliminate-dead-branches",
    "--eliminate-dead-code-aggressive",
    "--merge-blocks",
];

/// Bumped when the cache's file format or key changes.
const CACHE_VERSION: u32 = 1;

/// How a kernel's module reached the driver.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// Specialized here, read from the disk cache.
    Cached,
    /// Specialized here by running `spirv-opt` (and stored in the cache).
    Optimized,
    /// The whole module, specialized by the driver.
    Driver,
}

/// Counts of kernels made since the process started, by how their module was made.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Stats {
    pub cached: u32,
    pub optimized: u32,
    pub driver: u32,
    /// Why `spirv-opt` could not specialize a kernel, the first time it could not
    /// (`None` when every kernel was specialized or the driver path was asked for).
    pub unavailable: Option<String>,
}

static CACHED: AtomicU32 = AtomicU32::new(0);
static OPTIMIZED: AtomicU32 = AtomicU32::new(0);
static DRIVER: AtomicU32 = AtomicU32::new(0);
static UNAVAILABLE: Mutex<Option<String>> = Mutex::new(None);

/// How many kernels were made each way so far in this process (for `render`'s
/// start-up line).
pub fn stats() -> Stats {
    Stats {
        cached: CACHED.load(Ordering::Relaxed),
        optimized: OPTIMIZED.load(Ordering::Relaxed),
        driver: DRIVER.load(Ordering::Relaxed),
        unavailable: UNAVAILABLE.lock().map(|u| u.clone()).unwrap_or(None),
    }
}

/// The module of kernel `name` with `constants` `(constant_id, 32-bit value)` written
/// in and the code they switch off removed, or `None` where the driver must apply them
/// (see the module documentation). `name` only labels the cache entry. With `inline`,
/// the module is also inlined into one function ([`INLINE_PASSES`]).
pub fn specialize(
    name: &str,
    spirv: &[u32],
    constants: &[(u32, u32)],
    inline: bool,
) -> Result<Option<Vec<u32>>, Error> {
    let (specialized, source) = match std::env::var("WAVETRACE_SPECIALIZE") {
        Err(_) => specialize_here(name, spirv, constants, inline),
        Ok(v) if v == "spirv-opt" => specialize_here(name, spirv, constants, inline),
        Ok(v) if v == "driver" => (None, Source::Driver),
        Ok(value) => {
            return Err(Error::Environment {
                var: "WAVETRACE_SPECIALIZE",
                value,
                expected: "spirv-opt (the default), driver",
            })
        }
    };
    let counter = match source {
        Source::Cached => &CACHED,
        Source::Optimized => &OPTIMIZED,
        Source::Driver => &DRIVER,
    };
    counter.fetch_add(1, Ordering::Relaxed);
    Ok(specialized)
}

fn specialize_here(
    name: &str,
    spirv: &[u32],
    constants: &[(u32, u32)],
    inline: bool,
) -> (Option<Vec<u32>>, Source) {
    let path = cache_path(name, spirv, constants, inline);
    if let Some(code) = path.as_ref().and_then(read_cached) {
        return (Some(code), Source::Cached);
    }
    let mut module = spirv.to_vec();
    if let Err(why) = write_constants(&mut module, constants) {
        note_unavailable(format!("kernel '{name}': {why}"));
        return (None, Source::Driver);
    }
    match optimize(&module, inline) {
        Ok(code) => {
            if let Some(path) = &path {
                store_cache_file(path, bytemuck::cast_slice::<u32, u8>(&code));
            }
            (Some(code), Source::Optimized)
        }
        Err(why) => {
            note_unavailable(why);
            (None, Source::Driver)
        }
    }
}

fn note_unavailable(why: String) {
    if let Ok(mut u) = UNAVAILABLE.lock() {
        u.get_or_insert(why);
    }
}

/// Writes `constants` as the default values of the module's specialization constants
/// (`OpSpecConstant*` decorated `SpecId`): a 32-bit scalar's literal, or a boolean's
/// opcode (true for any nonzero value, as Vulkan reads a `VkBool32`). Ids the module
/// does not declare are skipped, as the driver skips them.
fn write_constants(module: &mut [u32], constants: &[(u32, u32)]) -> Result<(), String> {
    if module.len() < 5 || module[0] != MAGIC {
        return Err("not a SPIR-V module".into());
    }
    // Result id -> SpecId, from the decorations (which precede the constants).
    let mut spec_ids = std::collections::HashMap::new();
    let mut at = 5;
    while at < module.len() {
        let word = module[at];
        let (count, opcode) = ((word >> 16) as usize, word & 0xffff);
        if count == 0 || at + count > module.len() {
            return Err(format!("malformed instruction at word {at}"));
        }
        let operands = &module[at + 1..at + count];
        match opcode {
            OP_DECORATE if operands.len() == 3 && operands[1] == DECORATION_SPEC_ID => {
                spec_ids.insert(operands[0], operands[2]);
            }
            OP_SPEC_CONSTANT_TRUE | OP_SPEC_CONSTANT_FALSE | OP_SPEC_CONSTANT => {
                let id = operands.get(1).copied().unwrap_or(u32::MAX);
                let value = spec_ids
                    .get(&id)
                    .and_then(|sid| constants.iter().find(|(c, _)| c == sid))
                    .map(|&(_, v)| v);
                if let Some(value) = value {
                    if opcode == OP_SPEC_CONSTANT {
                        // Result type, result id, one literal word for a 32-bit scalar.
                        if count != 4 {
                            return Err(format!(
                                "specialization constant %{id} is not a 32-bit scalar"
                            ));
                        }
                        module[at + 3] = value;
                    } else {
                        let op = match value {
                            0 => OP_SPEC_CONSTANT_FALSE,
                            _ => OP_SPEC_CONSTANT_TRUE,
                        };
                        module[at] = (word & 0xffff_0000) | op;
                    }
                }
            }
            _ => {}
        }
        at += count;
    }
    Ok(())
}

/// Runs `spirv-opt`'s [`PASSES`] (and with `inline` [`INLINE_PASSES`]) over `module`
/// (through its standard input and output).
fn optimize(module: &[u32], inline: bool) -> Result<Vec<u32>, String> {
    let program = std::env::var("WAVETRACE_SPIRV_OPT").unwrap_or_else(|_| "spirv-opt".into());
    let mut child = Command::new(&program)
        .args(PASSES)
        .args(if inline { INLINE_PASSES } else { &[] })
        .args(["-", "-o", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            format!(
                "cannot run `{program}` ({e}); install it (sudo apt-get install spirv-tools) \
                 for a faster start-up"
            )
        })?;
    let mut stdin = child.stdin.take().ok_or("no stdin")?;
    let bytes: Vec<u8> = bytemuck::cast_slice(module).to_vec();
    // Written from a thread so a module larger than the pipe cannot deadlock against
    // spirv-opt's output.
    let writer = std::thread::spawn(move || stdin.write_all(&bytes));
    let output = child
        .wait_with_output()
        .map_err(|e| format!("`{program}` failed: {e}"))?;
    let written = writer
        .join()
        .map_err(|_| "writer thread panicked".to_string())?;
    if !output.status.success() {
        return Err(format!(
            "`{program}` failed ({}): {}",
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        ));
    }
    written.map_err(|e| format!("writing to `{program}`: {e}"))?;
    words(&output.stdout).ok_or_else(|| format!("`{program}` wrote no SPIR-V module"))
}

/// The bytes as SPIR-V words, if they hold a module.
fn words(bytes: &[u8]) -> Option<Vec<u32>> {
    if !bytes.len().is_multiple_of(4) || bytes.len() < 20 {
        return None;
    }
    let words: Vec<u32> = bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    (words[0] == MAGIC).then_some(words)
}

/// Where the specialized module of (`spirv`, `constants`) is kept: named by the kernel
/// and a 128-bit hash of the passes, the module and the constants.
fn cache_path(
    name: &str,
    spirv: &[u32],
    constants: &[(u32, u32)],
    inline: bool,
) -> Option<PathBuf> {
    let root = super::device::cache_dir()?;
    Some(cache_file(&root, name, spirv, constants, inline))
}

/// [`cache_path`] under the cache folder `root`.
fn cache_file(
    root: &std::path::Path,
    name: &str,
    spirv: &[u32],
    constants: &[(u32, u32)],
    inline: bool,
) -> PathBuf {
    let dir = root.join("spirv");
    let passes = (PASSES, inline.then_some(INLINE_PASSES));
    let hash = |salt: u64| {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        (salt, CACHE_VERSION, passes, spirv, constants).hash(&mut h);
        h.finish()
    };
    let label: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    dir.join(format!("{label}-{:016x}{:016x}.spv", hash(0), hash(1)))
}

fn read_cached(path: &PathBuf) -> Option<Vec<u32>> {
    words(&std::fs::read(path).ok()?)
}

/// Stores a cache file (a specialized module, the pipeline cache): written to a file of
/// its own (this process's, a counter's), then renamed into place, so readers and other
/// processes writing the same entry never see a partial file. Failures only cost time.
pub(crate) fn store_cache_file(path: &std::path::Path, bytes: &[u8]) {
    static TEMP: AtomicU32 = AtomicU32::new(0);
    let Some(dir) = path.parent() else { return };
    if std::fs::create_dir_all(dir).is_err() {
        return;
    }
    let n = TEMP.fetch_add(1, Ordering::Relaxed);
    let tmp = path.with_extension(format!("{}-{n}.tmp", std::process::id()));
    if std::fs::write(&tmp, bytes).is_ok() && std::fs::rename(&tmp, path).is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A module's SpecId -> (opcode, literal) of its scalar specialization constants.
    fn constants_of(module: &[u32]) -> std::collections::HashMap<u32, (u32, Option<u32>)> {
        let mut spec_ids = std::collections::HashMap::new();
        let mut out = std::collections::HashMap::new();
        let mut at = 5;
        while at < module.len() {
            let count = (module[at] >> 16) as usize;
            let opcode = module[at] & 0xffff;
            let ops = &module[at + 1..at + count];
            if opcode == OP_DECORATE && ops.len() == 3 && ops[1] == DECORATION_SPEC_ID {
                spec_ids.insert(ops[0], ops[2]);
            }
            if matches!(
                opcode,
                OP_SPEC_CONSTANT_TRUE | OP_SPEC_CONSTANT_FALSE | OP_SPEC_CONSTANT
            ) {
                if let Some(&sid) = spec_ids.get(&ops[1]) {
                    out.insert(sid, (opcode, ops.get(2).copied()));
                }
            }
            at += count;
        }
        out
    }

    fn module(bytes: &[u8]) -> Vec<u32> {
        words(bytes).expect("a SPIR-V module")
    }

    #[test]
    fn constants_are_written_into_the_module() {
        // shade declares integers (0: the integrator, 1: BSDF kinds, 5: the quadric
        // kinds) and a boolean (4: media).
        let mut m = module(crate::gpu::shaders::SHADE);
        let before = constants_of(&m);
        assert_eq!(before[&4].0, OP_SPEC_CONSTANT_FALSE);
        assert_eq!(before[&5], (OP_SPEC_CONSTANT, Some(0xffff_ffff)));
        write_constants(&mut m, &[(0, 7), (1, 0x2a), (4, 1), (5, 0), (999, 3)]).unwrap();
        let after = constants_of(&m);
        assert_eq!(after[&0], (OP_SPEC_CONSTANT, Some(7)));
        assert_eq!(after[&1], (OP_SPEC_CONSTANT, Some(0x2a)));
        assert_eq!(after[&4].0, OP_SPEC_CONSTANT_TRUE);
        assert_eq!(after[&5], (OP_SPEC_CONSTANT, Some(0)));
        // Constants not given keep their defaults.
        assert_eq!(after[&2], before[&2]);
        assert_eq!(m.len(), module(crate::gpu::shaders::SHADE).len());
    }

    #[test]
    fn malformed_modules_are_refused() {
        assert!(write_constants(&mut [1, 2, 3], &[]).is_err());
        let mut m = module(crate::gpu::shaders::QUEUE_ARGS);
        let n = m.len();
        // An instruction claiming more words than the module holds.
        m[5] = 0xffff_0000 | (m[5] & 0xffff);
        assert!(write_constants(&mut m[..n], &[]).is_err());
        assert!(words(&[1, 2, 3]).is_none());
    }

    /// The media cube's `first_bounce` as llvmpipe at 16 lanes runs it (its 16
    /// primitives tested in turn, in four traversals that each inline every step)
    /// specializes with spirv-opt: before the constant arguments were propagated ahead
    /// of the SSA rewrite ([`INLINE_PASSES`]) the inlined module passed spirv-opt's
    /// limit of 4,194,303 ids, spirv-opt crashed, and the driver took 68 s over it.
    #[test]
    fn the_media_cube_first_bounce_specializes_inlined() {
        use crate::gpu::device::DeviceInfo;
        use crate::render::plan::{layout_constants, RenderPlan, Stage};
        if Command::new("spirv-opt").arg("--version").output().is_err() {
            eprintln!("skipped: spirv-opt is not installed");
            return;
        }
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/media/cube.xml");
        let scene = crate::scene::load(&path, &[("res".into(), "256".into())]).expect("cube.xml");
        let wide = DeviceInfo {
            name: "llvmpipe (LLVM 22.1.8, 512 bits)".into(),
            scene_storage: true,
            ..DeviceInfo::lavapipe_for_tests()
        };
        let plan = RenderPlan::new(&scene, &Default::default(), &wide).expect("a plan");
        assert_eq!((plan.flat.count, plan.flat.flat_only), (16, true));
        let kernel = plan
            .kernel(Stage::FirstBounce)
            .expect("first_bounce is planned");
        let spirv = crate::gpu::shaders::scene_storage_variant(kernel.stage.spirv())
            .expect("first_bounce has a storage-buffer variant");
        let mut m = module(spirv);
        let mut constants = kernel.spec.ids();
        constants.extend(layout_constants(&wide).ids());
        write_constants(&mut m, &constants).expect("constants written");
        if let Err(why) = optimize(&m, true) {
            panic!("first_bounce of media/cube.xml: {why}");
        }
    }

    #[test]
    fn cache_keys_differ_by_module_constants_and_passes() {
        // A cache folder of this test's own, so the keys are compared whatever HOME
        // and XDG_CACHE_HOME say.
        let root = std::env::temp_dir().join(format!("wavetrace-cachekeys-{}", std::process::id()));
        let m = module(crate::gpu::shaders::SHADE);
        let key =
            |m: &[u32], c: u32, inline: bool| cache_file(&root, "shade", m, &[(0, c)], inline);
        let a = key(&m, 1, false);
        assert!(a.starts_with(root.join("spirv")), "{}", a.display());
        assert_ne!(a, key(&m, 2, false));
        assert_ne!(a, key(&m[..m.len() - 1], 1, false));
        assert_eq!(a, key(&m, 1, false));
        assert_ne!(a, key(&m, 1, true));
        // An entry stored under the key is read back whole.
        store_cache_file(&a, bytemuck::cast_slice::<u32, u8>(&m));
        assert_eq!(read_cached(&a).as_deref(), Some(&m[..]));
        let _ = std::fs::remove_dir_all(&root);
    }
}
