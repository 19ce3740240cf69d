//! The scene in GPU buffers: descriptor set 0 of every kernel that reads the scene
//! (`shaders/common/scene_bindings.glsl`).

use crate::accel::Bvh;
use crate::gpu::layout::{
    BsdfRecord, EmitterRecord, ShapeRecord, TriangleRecord, Vertex, EMITTER_AREA, EMITTER_CONSTANT,
    EMITTER_POINT, NONE, SHAPE_FLIP_NORMALS, SHAPE_HAS_NORMALS, SHAPE_HAS_UVS,
};
use crate::gpu::{BindingLayout, Buffer, DescriptorSet, Device};
use crate::scene::{Emitter, Scene};

use super::error::Result;

/// Bindings of set 0, in order.
pub const SCENE_BINDINGS: u32 = 7;

/// Host-side records of a scene, before upload. Built without a GPU so it can be
/// tested and inspected.
#[derive(Debug, Default, Clone)]
pub struct SceneRecords {
    pub shapes: Vec<ShapeRecord>,
    pub triangles: Vec<TriangleRecord>,
    pub vertices: Vec<Vertex>,
    pub bsdfs: Vec<BsdfRecord>,
    /// Point lights first, then the rest; see `point_light_count`.
    pub emitters: Vec<EmitterRecord>,
    pub point_light_count: u32,
}

impl SceneRecords {
    pub fn new(scene: &Scene) -> SceneRecords {
        let mut r = SceneRecords::default();
        // Emitters: point lights first so the shading code can pick among them by
        // index; `remap[i]` is the new index of scene emitter i.
        let mut order: Vec<usize> = (0..scene.emitters.len()).collect();
        order.sort_by_key(|&i| !matches!(scene.emitters[i], Emitter::Point { .. }));
        let mut remap = vec![NONE; scene.emitters.len()];
        for (new, &old) in order.iter().enumerate() {
            remap[old] = new as u32;
            let rec = match scene.emitters[old] {
                Emitter::Point {
                    position,
                    intensity,
                } => {
                    r.point_light_count += 1;
                    EmitterRecord {
                        position: position.into(),
                        kind: EMITTER_POINT,
                        radiance: intensity.into(),
                        shape: NONE,
                    }
                }
                Emitter::Area { radiance } => EmitterRecord {
                    kind: EMITTER_AREA,
                    radiance: radiance.into(),
                    shape: NONE,
                    ..Default::default()
                },
                Emitter::Constant { radiance } => EmitterRecord {
                    kind: EMITTER_CONSTANT,
                    radiance: radiance.into(),
                    shape: NONE,
                    ..Default::default()
                },
            };
            r.emitters.push(rec);
        }
        let emitter_of = |e: Option<u32>| e.map(|i| remap[i as usize]).unwrap_or(NONE);

        for (shape_index, mesh) in scene.meshes.iter().enumerate() {
            let base = r.vertices.len() as u32;
            let has_n = !mesh.normals.is_empty();
            let has_uv = !mesh.uvs.is_empty();
            let mut flags = 0;
            if has_n {
                flags |= SHAPE_HAS_NORMALS;
            }
            if has_uv {
                flags |= SHAPE_HAS_UVS;
            }
            if has_n || has_uv {
                for i in 0..mesh.positions.len() {
                    let n = mesh.normals.get(i).copied().unwrap_or_default();
                    let uv = mesh.uvs.get(i).copied().unwrap_or_default();
                    r.vertices.push(Vertex {
                        nx: n.x,
                        ny: n.y,
                        nz: n.z,
                        u: uv.x,
                        v: uv.y,
                    });
                }
            }
            for t in &mesh.indices {
                r.triangles.push(TriangleRecord {
                    v0: base + t[0],
                    v1: base + t[1],
                    v2: base + t[2],
                });
            }
            if let Some(e) = mesh.emitter {
                r.emitters[remap[e as usize] as usize].shape = shape_index as u32;
            }
            r.shapes.push(ShapeRecord {
                bsdf: mesh.bsdf,
                emitter: emitter_of(mesh.emitter),
                flags,
                pad0: 0,
            });
        }
        for sphere in &scene.spheres {
            let shape_index = r.shapes.len() as u32;
            if let Some(e) = sphere.emitter {
                r.emitters[remap[e as usize] as usize].shape = shape_index;
            }
            r.shapes.push(ShapeRecord {
                bsdf: sphere.bsdf,
                emitter: emitter_of(sphere.emitter),
                flags: if sphere.flip_normals {
                    SHAPE_FLIP_NORMALS
                } else {
                    0
                },
                pad0: 0,
            });
        }
        r.bsdfs = scene.bsdfs.iter().map(BsdfRecord::from).collect();
        r
    }
}

/// The scene's buffers on the device and the descriptor set binding them.
pub struct SceneBuffers {
    _buffers: Vec<Buffer>,
    pub set: DescriptorSet,
}

impl SceneBuffers {
    pub fn upload(
        device: &Device,
        layout: &BindingLayout,
        bvh: &Bvh,
        records: &SceneRecords,
    ) -> Result<SceneBuffers> {
        let buffers = vec![
            Buffer::from_slice(device, "bvh nodes", &bvh.nodes)?,
            Buffer::from_slice(device, "primitives", &bvh.prims)?,
            Buffer::from_slice(device, "shapes", &records.shapes)?,
            Buffer::from_slice(device, "triangles", &records.triangles)?,
            Buffer::from_slice(device, "vertices", &records.vertices)?,
            Buffer::from_slice(device, "bsdfs", &records.bsdfs)?,
            Buffer::from_slice(device, "emitters", &records.emitters)?,
        ];
        debug_assert_eq!(buffers.len() as u32, SCENE_BINDINGS);
        let refs: Vec<&Buffer> = buffers.iter().collect();
        let set = DescriptorSet::new(layout, 0, &refs)?;
        Ok(SceneBuffers {
            _buffers: buffers,
            set,
        })
    }
}
