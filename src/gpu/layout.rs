//! Every struct the host shares with the kernels, declared once.
//!
//! Each is `#[repr(C)]` with explicit padding to GLSL's std430 rules and mirrored field
//! for field, with the same names, in `shaders/common/layout.glsl`. The test at the
//! bottom parses that file, computes std430 offsets and checks them against these.

use bytemuck::{Pod, Zeroable};

/// A BVH2 node holding the bounds of both its children (Aila and Laine 2009,
/// "Understanding the Efficiency of Ray Traversal on GPUs"): one fetch tests both.
///
/// For each child: `count == 0` means `index` is an inner node in the node array;
/// `count > 0` means a leaf holding primitives `index .. index + count` of the
/// primitive array. An absent child has an empty box (min = +inf, max = -inf).
/// The root is node 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub left_min: [f32; 3],
    pub left_index: u32,
    pub left_max: [f32; 3],
    pub left_count: u32,
    pub right_min: [f32; 3],
    pub right_index: u32,
    pub right_max: [f32; 3],
    pub right_count: u32,
}

/// Primitive kinds in [`Prim::kind`].
pub const PRIM_TRIANGLE: u32 = 0;
pub const PRIM_SPHERE: u32 = 1;

/// One primitive, in BVH leaf order.
///
/// Triangle: `p0`, `p1`, `p2` are its world-space vertices and `index` its global
/// triangle number (into [`TriangleAttr`]s). Sphere: `p0` is the center, `p1[0]` the
/// radius, `index` the sphere number. `shape` indexes [`ShapeRecord`]s.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Prim {
    pub p0: [f32; 3],
    pub shape: u32,
    pub p1: [f32; 3],
    pub index: u32,
    pub p2: [f32; 3],
    pub kind: u32,
}
