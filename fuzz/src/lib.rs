//! What the fuzz targets share: a file for each input, the folder of files a fuzzed
//! scene may refer to, the check that an error names its file, and an allocator that
//! treats any single huge allocation as a finding.
//!
//! wavetrace's loaders take paths (a scene resolves its meshes, textures and grids
//! against its own folder), so each input is written to a file in a folder of this
//! process (under `/dev/shm` where there is one) and loaded from there, as a user's
//! file would be.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The largest single allocation a fuzz input may cause. In fuzz builds images are
/// limited to 2^20 texels (`wavetrace::image::MAX_TEXELS`, 12 MiB as float RGB) and
/// EXR blocks to 16 MiB; grids are at most 2^25 values (128 MiB); meshes and
/// uncompressed formats are checked against the file's size, and inputs are at most
/// 64 KiB. A request above this comes from a size a header claimed that nothing
/// checked: a runaway allocation.
pub const MAX_ALLOCATION: usize = 256 << 20;

/// [`System`], aborting (a crash libFuzzer records, with the input) on a request
/// larger than [`MAX_ALLOCATION`].
pub struct LimitedAlloc;

unsafe impl GlobalAlloc for LimitedAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        check(layout.size());
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        check(layout.size());
        System.alloc_zeroed(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        check(new_size);
        System.realloc(ptr, layout, new_size)
    }
}

fn check(size: usize) {
    if size > MAX_ALLOCATION {
        // The backtrace allocates only small blocks, which pass this check.
        eprintln!(
            "wavetrace-fuzz: runaway allocation of {size} bytes at once (over {MAX_ALLOCATION}) at\n{}",
            std::backtrace::Backtrace::force_capture()
        );
        std::process::abort();
    }
}

#[global_allocator]
static ALLOCATOR: LimitedAlloc = LimitedAlloc;

/// This process's scratch folder (created once).
fn scratch() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let shm = Path::new("/dev/shm");
        let base = if shm.is_dir() {
            shm.to_path_buf()
        } else {
            std::env::temp_dir()
        };
        let dir = base.join(format!("wavetrace-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("create the fuzz scratch folder");
        dir
    })
}

/// Writes `data` to the file `name` in the scratch folder and returns its path.
pub fn input_file(name: &str, data: &[u8]) -> PathBuf {
    let path = scratch().join(name);
    std::fs::write(&path, data).expect("write the fuzz input");
    path
}

/// The small files a fuzzed scene may name (`fuzz/fixtures`): meshes, textures, an
/// environment map, a grid and an include fragment.
pub const FIXTURES: &[(&str, &[u8])] = &[
    ("mesh.obj", include_bytes!("../fixtures/mesh.obj")),
    ("mesh.ply", include_bytes!("../fixtures/mesh.ply")),
    ("mesh_le.ply", include_bytes!("../fixtures/mesh_le.ply")),
    ("mesh_be.ply", include_bytes!("../fixtures/mesh_be.ply")),
    (
        "mesh.serialized",
        include_bytes!("../fixtures/mesh.serialized"),
    ),
    ("tex.png", include_bytes!("../fixtures/tex.png")),
    ("tex.jpg", include_bytes!("../fixtures/tex.jpg")),
    ("tex.exr", include_bytes!("../fixtures/tex.exr")),
    ("env.hdr", include_bytes!("../fixtures/env.hdr")),
    ("grid.vol", include_bytes!("../fixtures/grid.vol")),
    ("grid.vdb", include_bytes!("../fixtures/grid.vdb")),
    ("inc.xml", include_bytes!("../fixtures/inc.xml")),
];

/// The folder a fuzzed scene is written to, holding [`FIXTURES`].
pub fn scene_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = scratch().join("scene");
        std::fs::create_dir_all(&dir).expect("create the scene folder");
        for (name, bytes) in FIXTURES {
            std::fs::write(dir.join(name), bytes).expect("write a fixture");
        }
        dir
    })
}

/// Splits a scene input into its `-D name=value` definitions (leading lines of that
/// form, as the command line would pass them) and the scene file's bytes.
pub fn split_defines(data: &[u8]) -> (Vec<(String, String)>, &[u8]) {
    let mut defines = Vec::new();
    let mut rest = data;
    while let Some(line) = rest.strip_prefix(b"-D ") {
        let end = line.iter().position(|&b| b == b'\n').unwrap_or(line.len());
        let Ok(def) = std::str::from_utf8(&line[..end]) else {
            break;
        };
        let Some((name, value)) = def.split_once('=') else {
            break;
        };
        defines.push((name.to_string(), value.to_string()));
        rest = line.get(end + 1..).unwrap_or(&[]);
    }
    (defines, rest)
}

/// Loads a fuzzed scene file (with its leading `-D` lines as definitions) and
/// carries it as far as a render goes without a device: the integrator, sampler and
/// film a render would use, the sample count, the BVH and the GPU records.
pub fn scene(data: &[u8]) {
    use wavetrace::render::{plan_render, scene_buffers::SceneRecords, RenderOptions};
    let (defines, xml) = split_defines(data);
    let dir = scene_dir();
    let path = dir.join("scene.xml");
    std::fs::write(&path, xml).expect("write the fuzz scene");
    let scene = match wavetrace::scene::load(&path, &defines) {
        Ok(scene) => scene,
        Err(e) => return names_a_file(&e.to_string(), dir),
    };
    let (_, sampler, geometry) = match plan_render(&scene, &RenderOptions::default()) {
        Ok(plan) => plan,
        Err(e) => return names_a_file(&e.to_string(), dir),
    };
    let (kw, kh) = geometry.key_size();
    let _ = sampler.sample_count(scene.spp, kw, kh);
    // The render refuses scenes with more primitives than a BVH holds; fuzzed scenes
    // are small.
    if scene.triangle_count() + scene.quadrics.len() < 1 << 16 {
        let bvh = wavetrace::accel::bvh::Bvh::for_shapes(&scene.meshes, &scene.quadrics);
        let _ = SceneRecords::new(&scene, &bvh);
    }
}

/// Asserts that an error message says which file it is about: a path in the fuzz
/// folder (the input or a file it names) or a path the input wrote.
pub fn names_a_file(message: &str, dir: &Path) {
    let named = message.contains(&*dir.to_string_lossy())
        || message.contains(".xml")
        || message.contains('/');
    assert!(named, "error names no file: {message}");
}

/// Asserts that an error about the single file `path` names it.
pub fn names_file(message: &str, path: &Path) {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy())
        .unwrap_or_default();
    assert!(
        message.contains(&*name),
        "error does not name the file '{name}': {message}"
    );
}

/// Reads an image as a texture or an environment map would (`input.<ext>`: the
/// extension picks the decoder, as for a user's file).
pub fn image(ext: &str, data: &[u8]) {
    let path = input_file(&format!("input.{ext}"), data);
    if let Err(e) = wavetrace::scene::texture::load_image(&path, false) {
        names_file(&e, &path);
    }
}
