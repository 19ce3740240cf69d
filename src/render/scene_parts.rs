//! How the scene's arrays are laid over the bindings of set 0, so that their size is
//! bounded by the device's memory and not by one binding.
//!
//! Kernels read every scene array through a storage texel buffer (`imageLoad`, see
//! [`BindingKind::Texels`]), and one texel-buffer view addresses at most
//! `maxTexelBufferElements` texels (lavapipe: 2^27, i.e. 2 GiB of 16-byte texels or
//! 512 MiB of 4-byte words) within one allocation (`maxMemoryAllocationSize`, lavapipe
//! 2 GiB). An array larger than that is cut into parts of `2^part_shift` texels, part
//! `p` holding texels `p 2^part_shift ..`, each bound at its own binding: part 0 at
//! the array's binding 0-14, further parts at bindings 15 and up ([`SceneArray`]).
//! There is no descriptor indexing on lavapipe, so a load from a split array tests
//! its part against each binding in turn (`scene_bindings.glsl`); the number of parts
//! of each array and the part size are specialization constants
//! ([`ScenePlan::spec`]), so an array in one part — every array of every scene that
//! fits, the common case — compiles to the single image load it always was.
//!
//! The arrays that can outgrow a binding (geometry, bitmaps, grids) have extra parts;
//! records that exist once per shape, BSDF, emitter, texture or medium do not.

use crate::accel::Bvh;
use crate::gpu::layout::MediumRecord;
use crate::gpu::{BindingKind, ByteSize, DeviceInfo, SceneAccess};

use super::error::{Error, Result};
use super::scene_buffers::SceneRecords;

/// One array of set 0: part 0 at binding `binding`, further parts at the bindings
/// [`extra_bindings`] gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SceneArray {
    /// Name in messages and in `wavetrace info`.
    pub label: &'static str,
    /// The GLSL image of part 0 (`scene_bindings.glsl`); part `p > 0` is `{glsl}_{p}`.
    pub glsl: &'static str,
    /// [`BindingKind::Texels`] (16-byte texels) or [`BindingKind::Words`] (4-byte).
    pub kind: BindingKind,
    /// Most parts it may be split into.
    pub max_parts: u32,
    /// What a user can do when it does not fit.
    pub remedy: &'static str,
}

const GEOMETRY: &str = "use fewer triangles (decimate the largest meshes)";
const RECORDS: &str = "simplify the scene";

/// Every array of set 0, in binding order of their first parts.
pub const SCENE_ARRAYS: [SceneArray; 15] = [
    array(
        "bvh nodes",
        "bvh_node_texels",
        BindingKind::Texels,
        4,
        GEOMETRY,
    ),
    array(
        "primitives",
        "prim_texels",
        BindingKind::Texels,
        4,
        GEOMETRY,
    ),
    array("shapes", "shape_texels", BindingKind::Texels, 1, RECORDS),
    array(
        "triangles",
        "triangle_texels",
        BindingKind::Texels,
        2,
        GEOMETRY,
    ),
    array(
        "vertices",
        "vertex_texels",
        BindingKind::Texels,
        2,
        "use fewer vertices, or drop vertex normals and uvs (face_normals=\"true\") where \
         the mesh does not need them",
    ),
    array("bsdfs", "bsdf_texels", BindingKind::Texels, 1, RECORDS),
    array(
        "emitters",
        "emitter_texels",
        BindingKind::Texels,
        1,
        RECORDS,
    ),
    array(
        "alias tables",
        "alias_texels",
        BindingKind::Texels,
        1,
        "use fewer emitting triangles",
    ),
    array(
        "textures",
        "texture_texels",
        BindingKind::Texels,
        1,
        RECORDS,
    ),
    array(
        "texels",
        "texel_words",
        BindingKind::Words,
        4,
        "downscale the largest bitmap textures",
    ),
    array(
        "sampling distributions",
        "dist_words",
        BindingKind::Words,
        2,
        "downscale the environment map or the emitter textures",
    ),
    array("media", "medium_texels", BindingKind::Texels, 1, RECORDS),
    array(
        "density grids",
        "grid_words",
        BindingKind::Words,
        4,
        "use coarser grid volumes",
    ),
    array(
        "majorant grids",
        "majorant_words",
        BindingKind::Words,
        1,
        "use coarser grid volumes",
    ),
    array(
        "packed density grids",
        "grid_packed_texels",
        BindingKind::Texels,
        2,
        "use coarser grid volumes",
    ),
];

const fn array(
    label: &'static str,
    glsl: &'static str,
    kind: BindingKind,
    max_parts: u32,
    remedy: &'static str,
) -> SceneArray {
    SceneArray {
        label,
        glsl,
        kind,
        max_parts,
        remedy,
    }
}

/// Bindings of set 0: the first parts, then every further part.
pub const SCENE_BINDINGS: u32 = {
    let mut n = 0;
    let mut a = 0;
    while a < SCENE_ARRAYS.len() {
        n += SCENE_ARRAYS[a].max_parts;
        a += 1;
    }
    n
};

/// Specialization constant (of every kernel reading the scene) holding log2 of the
/// texels in one part (`SCENE_PART_SHIFT` in scene_bindings.glsl).
pub const SPEC_PART_SHIFT: u32 = 64;

/// Specialization constant holding the number of parts of array `a` (binding `a`):
/// `SPEC_PARTS_BASE + a`, for arrays with `max_parts > 1` (`*_PARTS` in
/// scene_bindings.glsl).
pub const SPEC_PARTS_BASE: u32 = 65;

/// The part shift the GLSL assumes without specialization; any value works for
/// arrays in one part.
pub const DEFAULT_PART_SHIFT: u32 = 27;

/// The bindings of parts `1..max_parts` of array `a`, in order.
pub fn extra_bindings(a: usize) -> std::ops::Range<u32> {
    let first = SCENE_ARRAYS.len() as u32
        + SCENE_ARRAYS[..a]
            .iter()
            .map(|s| s.max_parts - 1)
            .sum::<u32>();
    first..first + SCENE_ARRAYS[a].max_parts - 1
}

/// The kind of each binding of set 0 (texel buffers: [`SceneAccess::Texels`] and
/// [`SceneAccess::Split`]).
pub fn scene_binding_kinds() -> Vec<BindingKind> {
    let mut kinds: Vec<BindingKind> = SCENE_ARRAYS.iter().map(|a| a.kind).collect();
    for a in &SCENE_ARRAYS {
        kinds.extend(std::iter::repeat_n(a.kind, a.max_parts as usize - 1));
    }
    kinds
}

/// The kind of each binding of set 0 for kernels that read the scene as `access` says:
/// every one a storage buffer for [`SceneAccess::Storage`].
pub fn scene_binding_kinds_for(access: SceneAccess) -> Vec<BindingKind> {
    match access {
        SceneAccess::Storage => vec![BindingKind::Storage; SCENE_BINDINGS as usize],
        SceneAccess::Texels | SceneAccess::Split => scene_binding_kinds(),
    }
}

/// Bytes in one texel of an array of this kind.
pub fn texel_bytes(kind: BindingKind) -> u64 {
    match kind {
        BindingKind::Words => 4,
        _ => 16,
    }
}

/// log2 of the texels one part may hold on `info`'s device: the largest power of two
/// within `maxTexelBufferElements` and, in 16-byte texels, within one allocation.
pub fn device_part_shift(info: &DeviceInfo) -> u32 {
    let texels = info
        .max_texel_buffer_elements
        .min(info.max_memory_allocation_size / 16)
        .max(1);
    63 - texels.leading_zeros()
}

/// The contents of one scene array, borrowed or owned: an owned array is freed as
/// soon as it is uploaded, so a large scene is not held twice over on a device whose
/// memory is the host's (lavapipe).
pub trait ArrayBytes {
    fn bytes(&self) -> &[u8];
}

impl<T: bytemuck::Pod> ArrayBytes for Vec<T> {
    fn bytes(&self) -> &[u8] {
        bytemuck::cast_slice(self)
    }
}

impl<T: bytemuck::Pod> ArrayBytes for &[T] {
    fn bytes(&self) -> &[u8] {
        bytemuck::cast_slice(self)
    }
}

/// Every array of set 0, in binding order.
pub type SceneArrays<'a> = [Box<dyn ArrayBytes + 'a>; 15];

/// The arrays of `bvh` and `records`, borrowed.
pub fn scene_arrays<'a>(bvh: &'a Bvh, records: &'a SceneRecords) -> SceneArrays<'a> {
    arrays(
        Box::new(bvh.nodes.as_slice()),
        Box::new(bvh.prims.as_slice()),
        records,
        [
            Box::new(records.triangles.as_slice()),
            Box::new(records.vertices.as_slice()),
            Box::new(records.texels.as_slice()),
            Box::new(records.distributions.as_slice()),
            or_zero(&records.grid_data, 4),
            or_zero(&records.packed_density, 16),
        ],
    )
}

/// The arrays of `bvh` and `records`, the large ones taken: the BVH, and the
/// triangles, vertices, texels, distributions and grids of `records` (left empty).
pub fn take_scene_arrays(bvh: Bvh, records: &mut SceneRecords) -> SceneArrays<'_> {
    let large: [Box<dyn ArrayBytes>; 6] = [
        Box::new(std::mem::take(&mut records.triangles)),
        Box::new(std::mem::take(&mut records.vertices)),
        Box::new(std::mem::take(&mut records.texels)),
        Box::new(std::mem::take(&mut records.distributions)),
        or_zero_owned(std::mem::take(&mut records.grid_data), 1),
        or_zero_owned(std::mem::take(&mut records.packed_density), 1),
    ];
    arrays(Box::new(bvh.nodes), Box::new(bvh.prims), records, large)
}

/// One zero record where `v` is empty (a binding must have a buffer).
fn or_zero<T: bytemuck::Pod>(v: &[T], record: usize) -> Box<dyn ArrayBytes + '_> {
    if v.is_empty() {
        Box::new(vec![0u8; record])
    } else {
        Box::new(v)
    }
}

fn or_zero_owned<T: bytemuck::Pod + 'static>(v: Vec<T>, records: usize) -> Box<dyn ArrayBytes> {
    if v.is_empty() {
        Box::new(vec![T::zeroed(); records])
    } else {
        Box::new(v)
    }
}

/// The arrays in binding order, from the BVH's two, `records`' small ones, and the six
/// large ones (triangles, vertices, texels, sampling distributions, density grids, packed
/// density grids).
fn arrays<'a>(
    nodes: Box<dyn ArrayBytes + 'a>,
    prims: Box<dyn ArrayBytes + 'a>,
    r: &'a SceneRecords,
    large: [Box<dyn ArrayBytes + 'a>; 6],
) -> SceneArrays<'a> {
    let [triangles, vertices, texels, distributions, grids, packed] = large;
    [
        nodes,
        prims,
        Box::new(r.shapes.as_slice()),
        triangles,
        vertices,
        Box::new(r.bsdfs.as_slice()),
        Box::new(r.emitter_array()),
        Box::new(r.alias.as_slice()),
        Box::new(r.textures.as_slice()),
        texels,
        distributions,
        or_zero(&r.media, std::mem::size_of::<MediumRecord>()),
        grids,
        or_zero(&r.majorants, 4),
        packed,
    ]
}

/// The size of each array, bytes.
pub fn array_sizes(arrays: &SceneArrays<'_>) -> [u64; 15] {
    std::array::from_fn(|a| arrays[a].bytes().len() as u64)
}

/// How each array of a scene is split: the outcome of [`ScenePlan::new`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScenePlan {
    /// log2 of the texels in one part.
    pub part_shift: u32,
    /// Parts of each array, in binding order (at least 1).
    pub parts: [u32; 15],
    /// Bytes of each array.
    pub bytes: [u64; 15],
}

impl ScenePlan {
    /// Splits arrays of `bytes[a]` bytes into parts of `2^part_shift` texels; an
    /// array needing more than its `max_parts` is an error naming it, its size, the
    /// limit and what to do.
    pub fn new(bytes: [u64; 15], part_shift: u32) -> Result<ScenePlan> {
        let mut parts = [1u32; 15];
        for (a, array) in SCENE_ARRAYS.iter().enumerate() {
            let part_bytes = texel_bytes(array.kind) << part_shift;
            let n = bytes[a].div_ceil(part_bytes).max(1);
            if n > array.max_parts as u64 {
                return Err(Error::SceneTooLarge {
                    label: array.label,
                    size: bytes[a],
                    limit: part_bytes * array.max_parts as u64,
                    bindings: array.max_parts,
                    remedy: array.remedy,
                });
            }
            parts[a] = n as u32;
        }
        Ok(ScenePlan {
            part_shift,
            parts,
            bytes,
        })
    }

    /// [`ScenePlan::new`] for arrays of `bytes` bytes ([`array_sizes`]) on a device;
    /// `part_shift` overrides the device's part size (smaller parts: for tests of the
    /// split path). Also refuses scenes larger than the device's memory.
    pub fn for_device(
        info: &DeviceInfo,
        bytes: [u64; 15],
        part_shift: Option<u32>,
    ) -> Result<ScenePlan> {
        let device_shift = device_part_shift(info);
        let shift = part_shift.map_or(device_shift, |s| s.min(device_shift));
        let plan = ScenePlan::new(bytes, shift)?;
        let total = plan.total_bytes();
        if info.device_memory > 0 && total > info.device_memory {
            return Err(Error::SceneMemory {
                needed: total,
                available: info.device_memory,
                largest: plan.largest(),
            });
        }
        Ok(plan)
    }

    /// Bytes of all arrays.
    pub fn total_bytes(&self) -> u64 {
        self.bytes.iter().sum()
    }

    /// The largest array: its label and size.
    pub fn largest(&self) -> String {
        let a = (0..15).max_by_key(|&a| self.bytes[a]).unwrap_or(0);
        format!("{} {}", SCENE_ARRAYS[a].label, ByteSize(self.bytes[a]))
    }

    /// Whether some array is split over more than one binding.
    pub fn is_split(&self) -> bool {
        self.parts.iter().any(|&p| p > 1)
    }

    /// How kernels read this scene on the device `info` describes, their layout
    /// binding `other_storage` storage buffers besides the scene's: split arrays
    /// through texel buffers; else from storage buffers where the device reads those
    /// faster ([`DeviceInfo::scene_storage`]), binds that many and every array fits
    /// one (`max_storage_buffer_range`); else through texel buffers.
    pub fn access(&self, info: &DeviceInfo, other_storage: u32) -> SceneAccess {
        let fits = self
            .bytes
            .iter()
            .all(|&b| b <= info.max_storage_buffer_range);
        if self.is_split() {
            SceneAccess::Split
        } else if info.scene_storage
            && fits
            && SCENE_BINDINGS + other_storage <= info.max_storage_buffers
        {
            SceneAccess::Storage
        } else {
            SceneAccess::Texels
        }
    }

    /// The specialization constants `(constant_id, value)` every kernel reading the
    /// scene needs (through [`crate::gpu::BindingLayout::with_spec`]).
    pub fn spec(&self) -> Vec<(u32, u32)> {
        let mut spec = vec![(SPEC_PART_SHIFT, self.part_shift)];
        for (a, array) in SCENE_ARRAYS.iter().enumerate() {
            if array.max_parts > 1 {
                spec.push((SPEC_PARTS_BASE + a as u32, self.parts[a]));
            }
        }
        spec
    }

    /// Byte range of part `p` of array `a` within its bytes.
    pub fn part_range(&self, a: usize, p: u32) -> std::ops::Range<usize> {
        let part_bytes = (texel_bytes(SCENE_ARRAYS[a].kind) << self.part_shift) as usize;
        let len = self.bytes[a] as usize;
        let start = (p as usize * part_bytes).min(len);
        start..(start + part_bytes).min(len)
    }

    /// Lines for `wavetrace info`: each array's device memory and parts.
    pub fn describe(&self) -> Vec<String> {
        let mut lines: Vec<String> = SCENE_ARRAYS
            .iter()
            .enumerate()
            .map(|(a, array)| {
                let parts = if self.parts[a] > 1 {
                    format!(" in {} bindings", self.parts[a])
                } else {
                    String::new()
                };
                format!(
                    "{:<22} {:>10}{parts}",
                    array.label,
                    ByteSize(self.bytes[a]).to_string()
                )
            })
            .collect();
        lines.push(format!(
            "{:<22} {:>10}",
            "all scene buffers",
            ByteSize(self.total_bytes()).to_string()
        ));
        lines
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extra_bindings_follow_the_first_parts_in_array_order() {
        assert_eq!(extra_bindings(0), 15..18);
        assert_eq!(extra_bindings(1), 18..21);
        assert_eq!(extra_bindings(2), 21..21);
        assert_eq!(extra_bindings(3), 21..22);
        assert_eq!(extra_bindings(14).end, SCENE_BINDINGS);
        assert_eq!(scene_binding_kinds().len() as u32, SCENE_BINDINGS);
        for (a, array) in SCENE_ARRAYS.iter().enumerate() {
            for b in extra_bindings(a) {
                assert_eq!(scene_binding_kinds()[b as usize], array.kind);
            }
        }
    }

    /// Storage buffers where the device prefers them, binds enough and the arrays fit;
    /// a split scene keeps its texel buffers.
    #[test]
    fn scene_access_follows_the_device() {
        let mut info = DeviceInfo::lavapipe_for_tests();
        let plan = ScenePlan::new([1 << 10; 15], DEFAULT_PART_SHIFT).unwrap();
        assert_eq!(plan.access(&info, 8), SceneAccess::Texels);
        info.scene_storage = true;
        info.max_storage_buffers = SCENE_BINDINGS + 8;
        assert_eq!(plan.access(&info, 8), SceneAccess::Storage);
        assert_eq!(plan.access(&info, 9), SceneAccess::Texels);
        info.max_storage_buffer_range = 1 << 9;
        assert_eq!(plan.access(&info, 8), SceneAccess::Texels);
        info.max_storage_buffer_range = 1 << 40;
        let mut bytes = [16; 15];
        bytes[0] = 1 << 10; // BVH nodes: 64 texels, in parts of 16
        let split = ScenePlan::new(bytes, 4).unwrap();
        assert!(split.is_split());
        assert_eq!(split.access(&info, 8), SceneAccess::Split);
        assert_eq!(
            scene_binding_kinds_for(SceneAccess::Storage),
            vec![BindingKind::Storage; SCENE_BINDINGS as usize]
        );
        assert_eq!(
            scene_binding_kinds_for(SceneAccess::Split),
            scene_binding_kinds()
        );
    }

    /// scene_bindings.glsl declares every part of every array at the binding, with the
    /// format and the parts constant this table gives it.
    #[test]
    fn glsl_bindings_mirror_the_table() {
        let glsl = include_str!("../../shaders/scene/scene_bindings.glsl");
        let declared = |binding: u32, name: &str, format: &str| {
            let decl = format!("\n{format}({binding}, {name})\n");
            assert!(glsl.contains(&decl), "scene_bindings.glsl lacks `{decl}`");
        };
        // The two declaring macros: a texel buffer of that format, or a storage buffer
        // of uvec4 or uint (SCENE_STORAGE).
        for decl in [
            "SCENE_TEXELS(b, NAME) layout(set = 0, binding = b, rgba32ui) uniform readonly uimageBuffer NAME;",
            "SCENE_WORDS(b, NAME) layout(set = 0, binding = b, r32ui) uniform readonly uimageBuffer NAME;",
            "readonly buffer NAME##_block { uvec4 NAME[]; };",
            "readonly buffer NAME##_block { uint NAME[]; };",
        ] {
            assert!(glsl.contains(decl), "scene_bindings.glsl lacks `{decl}`");
        }
        let mut declarations = 0;
        for (a, array) in SCENE_ARRAYS.iter().enumerate() {
            let format = match array.kind {
                BindingKind::Words => "SCENE_WORDS",
                _ => "SCENE_TEXELS",
            };
            declared(a as u32, array.glsl, format);
            for (p, b) in extra_bindings(a).enumerate() {
                declared(b, &format!("{}_{}", array.glsl, p + 1), format);
            }
            declarations += array.max_parts;
            if array.max_parts > 1 {
                let id = SPEC_PARTS_BASE + a as u32;
                let macro_ = format!("SCENE_ARRAY_{}(", array.max_parts);
                let use_ = glsl
                    .lines()
                    .find(|l| l.starts_with(&macro_) && l.contains(&format!(" {},", array.glsl)))
                    .unwrap_or_else(|| panic!("no {macro_}.., {}, ..)", array.glsl));
                let parts = use_.trim_end_matches(')').rsplit(' ').next().unwrap();
                assert_spec_declared(glsl, id, parts, 1);
            }
        }
        let declaring = |l: &&str| {
            (l.starts_with("SCENE_TEXELS(") || l.starts_with("SCENE_WORDS(")) && l.ends_with(')')
        };
        assert_eq!(glsl.lines().filter(declaring).count() as u32, declarations);
        assert_spec_declared(
            glsl,
            SPEC_PART_SHIFT,
            "SCENE_PART_SHIFT",
            DEFAULT_PART_SHIFT,
        );
    }

    /// scene_bindings.glsl declares constant `name` by name (`SPEC(name);`), and the
    /// header build.rs generates from the table of constants gives it `id` and the
    /// default `value`.
    fn assert_spec_declared(glsl: &str, id: u32, name: &str, value: u32) {
        let uses = format!("SPEC({name});");
        assert!(glsl.contains(&uses), "scene_bindings.glsl lacks `{uses}`");
        let header = include_str!(concat!(
            env!("OUT_DIR"),
            "/glsl/generated/spec_constants.glsl"
        ));
        let decl =
            format!("#define SPEC_{name} layout(constant_id = {id}) const uint {name} = {value}u");
        assert!(header.contains(&decl), "spec_constants.glsl lacks `{decl}`");
    }

    #[test]
    fn arrays_split_into_whole_parts_and_refuse_past_their_bindings() {
        let mut bytes = [16u64; 15];
        bytes[1] = 3 * 16 * 1000 + 16; // primitives: 3001 texels
        bytes[9] = 4 * 1024; // texels: exactly one part of 1024 words
        let plan = ScenePlan::new(bytes, 10).unwrap();
        assert_eq!(plan.parts[1], 3);
        assert_eq!(plan.parts[9], 1);
        assert_eq!(plan.part_range(1, 0), 0..16 << 10);
        assert_eq!(plan.part_range(1, 2), 2 * (16 << 10)..bytes[1] as usize);
        assert!(plan.is_split());
        assert!(plan.spec().contains(&(SPEC_PARTS_BASE + 1, 3)));
        assert!(plan.spec().contains(&(SPEC_PART_SHIFT, 10)));

        bytes[0] = 5 * (16 << 10); // bvh nodes: five parts, four bindings
        let e = ScenePlan::new(bytes, 10).unwrap_err().to_string();
        for part in [
            "bvh nodes",
            "80.0 KiB",
            "64.0 KiB",
            "4 bindings",
            "decimate",
        ] {
            assert!(e.contains(part), "{e}\n  wanted: {part}");
        }
        bytes[0] = 16;
        bytes[2] = 2 * (16 << 10); // shapes: never split
        let e = ScenePlan::new(bytes, 10).unwrap_err().to_string();
        assert!(e.contains("shapes") && e.contains("1 binding"), "{e}");
    }

    #[test]
    fn lavapipe_parts_are_two_gib_of_texels() {
        let info = DeviceInfo::lavapipe_for_tests();
        assert_eq!(device_part_shift(&info), 27);
        let one_gib = DeviceInfo {
            max_memory_allocation_size: 1 << 30,
            ..info
        };
        assert_eq!(device_part_shift(&one_gib), 26);
    }
}
