//! Compute kernels: binding layouts, descriptor sets and pipelines.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use ash::vk;

use super::buffer::Buffer;
use super::device::{Device, Inner};
use super::error::{Error, Result, VkContext};
use super::spec::SpecValues;

/// What a binding holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BindingKind {
    /// A storage buffer (`buffer` block in GLSL), read and written by any access.
    Storage,
    /// A buffer of 16-byte texels read as a storage texel buffer (`layout(rgba32ui)
    /// readonly uimageBuffer`, read with `imageLoad` as `uvec4`). For records read at
    /// scattered addresses in hot loops: llvmpipe compiles a divergent storage-buffer
    /// load into a loop over the SIMD lanes with a branch per lane, and an image load
    /// into one unrolled gather inline. (A `texelFetch` from a uniform texel buffer
    /// gathers alike but through a call to llvmpipe's texel-fetch function for any
    /// format but 8-bit RGBA: the Cornell box rendered 15% slower with it.)
    Texels,
    /// As `Texels`, of 4-byte texels (`layout(r32ui) readonly uimageBuffer`, read as
    /// `imageLoad(..).x`), for records whose size is not a multiple of 16 bytes.
    Words,
    /// A uniform buffer (`uniform` block, std140): small read-only data such as the
    /// frame's parameters, which llvmpipe loads without a per-lane loop even inside
    /// divergent control flow.
    Uniform,
}

/// How the kernels of a layout read the scene's arrays (`scene_bindings.glsl`), which
/// picks the variant of every kernel that reads them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SceneAccess {
    /// Image loads from storage texel buffers, an array at one binding: the plain
    /// kernels.
    #[default]
    Texels,
    /// Image loads, arrays split over several bindings: the `SCENE_SPLIT` variants
    /// ([`super::shaders::scene_split_variant`]).
    Split,
    /// Loads from storage buffers, an array at one binding: the `SCENE_STORAGE`
    /// variants ([`super::shaders::scene_storage_variant`]), for devices where they
    /// are faster ([`DeviceInfo::scene_storage`](super::DeviceInfo)).
    Storage,
}

impl BindingKind {
    fn descriptor_type(self) -> vk::DescriptorType {
        match self {
            BindingKind::Storage => vk::DescriptorType::STORAGE_BUFFER,
            BindingKind::Texels | BindingKind::Words => vk::DescriptorType::STORAGE_TEXEL_BUFFER,
            BindingKind::Uniform => vk::DescriptorType::UNIFORM_BUFFER,
        }
    }

    fn texel_format(self) -> Option<vk::Format> {
        match self {
            BindingKind::Texels => Some(vk::Format::R32G32B32A32_UINT),
            BindingKind::Words => Some(vk::Format::R32_UINT),
            BindingKind::Storage | BindingKind::Uniform => None,
        }
    }
}

struct LayoutInner {
    device: Arc<Inner>,
    set_layouts: Vec<vk::DescriptorSetLayout>,
    kinds: Vec<Vec<BindingKind>>,
    pipeline_layout: vk::PipelineLayout,
    push_bytes: u32,
    /// Specialization constants `(constant_id, value)` every kernel of this layout gets.
    spec: Vec<(u32, u32)>,
    /// Which variant of kernels that read the scene runs.
    scene: SceneAccess,
}

impl Drop for LayoutInner {
    fn drop(&mut self) {
        // SAFETY: kernels and sets using this layout hold an Arc to it.
        unsafe {
            self.device
                .raw
                .destroy_pipeline_layout(self.pipeline_layout, None);
            for &l in &self.set_layouts {
                self.device.raw.destroy_descriptor_set_layout(l, None);
            }
        }
    }
}

/// A kernel to create with [`Kernel::new_all`]: its name, SPIR-V and the values of
/// its own specialization constants, `(constant_id, value)`.
pub struct KernelSpec<'a> {
    pub name: &'a str,
    pub spirv: &'a [u8],
    pub spec: Vec<(u32, u32)>,
    /// Inline the module into one function before the driver sees it (see
    /// `specialize::INLINE_PASSES`: faster to create on lavapipe, slower to run where
    /// functions with early returns run inside loops).
    pub inline: bool,
}

impl<'a> KernelSpec<'a> {
    /// A kernel whose constants are numbered by position: `spec[i]` is constant_id `i`
    /// (the test kernels of shaders/tests/).
    pub fn new(name: &'a str, spirv: &'a [u8], spec: &[u32]) -> KernelSpec<'a> {
        KernelSpec {
            name,
            spirv,
            spec: (0..).zip(spec.iter().copied()).collect(),
            inline: false,
        }
    }

    /// A kernel whose constants are set by name (the table of `gpu::spec_ids`).
    pub fn named(name: &'a str, spirv: &'a [u8], spec: &SpecValues) -> KernelSpec<'a> {
        KernelSpec {
            name,
            spirv,
            spec: spec.ids(),
            inline: false,
        }
    }

    /// The kernel, inlined where `inline` says ([`KernelSpec::inline`]).
    pub fn inlined(self, inline: bool) -> KernelSpec<'a> {
        KernelSpec { inline, ..self }
    }
}

/// The resource interface kernels share: descriptor sets of buffers and a
/// push-constant block.
#[derive(Clone)]
pub struct BindingLayout {
    inner: Arc<LayoutInner>,
}

impl BindingLayout {
    /// Sets made only of storage buffers, `set_sizes[s]` bindings in set `s`.
    pub fn new(device: &Device, set_sizes: &[u32], push_bytes: u32) -> Result<BindingLayout> {
        let kinds: Vec<Vec<BindingKind>> = set_sizes
            .iter()
            .map(|&n| vec![BindingKind::Storage; n as usize])
            .collect();
        BindingLayout::with_kinds(device, &kinds, push_bytes)
    }

    /// Set `s` has binding `b` of kind `kinds[s][b]`.
    pub fn with_kinds(
        device: &Device,
        kinds: &[Vec<BindingKind>],
        push_bytes: u32,
    ) -> Result<BindingLayout> {
        BindingLayout::with_spec(device, kinds, push_bytes, &[], SceneAccess::Texels)
    }

    /// [`BindingLayout::with_kinds`], plus specialization constants `(constant_id,
    /// value)` that every [`Kernel`] made with this layout gets: facts about the bound
    /// data that all kernels reading it must agree on (how the scene's arrays are split
    /// over bindings, `render::scene_parts`). Their ids must lie above those kernels
    /// number themselves. Kernels that read the scene run the variant `scene` says.
    pub fn with_spec(
        device: &Device,
        kinds: &[Vec<BindingKind>],
        push_bytes: u32,
        spec: &[(u32, u32)],
        scene: SceneAccess,
    ) -> Result<BindingLayout> {
        let raw = device.raw();
        let mut set_layouts = Vec::new();
        for set in kinds {
            let bindings: Vec<_> = set
                .iter()
                .enumerate()
                .map(|(b, kind)| {
                    vk::DescriptorSetLayoutBinding::default()
                        .binding(b as u32)
                        .descriptor_type(kind.descriptor_type())
                        .descriptor_count(1)
                        .stage_flags(vk::ShaderStageFlags::COMPUTE)
                })
                .collect();
            let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
            // SAFETY: valid create info.
            match unsafe { raw.create_descriptor_set_layout(&info, None) } {
                Ok(l) => set_layouts.push(l),
                Err(result) => {
                    for l in set_layouts {
                        // SAFETY: unused layouts of this device.
                        unsafe { raw.destroy_descriptor_set_layout(l, None) };
                    }
                    return Err(Error::Vk {
                        call: "vkCreateDescriptorSetLayout",
                        result,
                    });
                }
            }
        }
        let ranges = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::COMPUTE)
            .offset(0)
            .size(push_bytes.max(4))];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_layouts)
            .push_constant_ranges(&ranges);
        // SAFETY: valid create info.
        let pipeline_layout = match unsafe { raw.create_pipeline_layout(&info, None) } {
            Ok(l) => l,
            Err(result) => {
                for l in set_layouts {
                    // SAFETY: unused layouts of this device.
                    unsafe { raw.destroy_descriptor_set_layout(l, None) };
                }
                return Err(Error::Vk {
                    call: "vkCreatePipelineLayout",
                    result,
                });
            }
        };
        Ok(BindingLayout {
            inner: Arc::new(LayoutInner {
                device: device.inner.clone(),
                set_layouts,
                kinds: kinds.to_vec(),
                pipeline_layout,
                push_bytes,
                spec: spec.to_vec(),
                scene,
            }),
        })
    }

    pub fn push_bytes(&self) -> u32 {
        self.inner.push_bytes
    }

    /// The specialization constants every kernel of this layout gets.
    pub fn spec(&self) -> &[(u32, u32)] {
        &self.inner.spec
    }

    /// Which variant of kernels that read the scene this layout's kernels run.
    pub fn scene_access(&self) -> SceneAccess {
        self.inner.scene
    }
}

/// One descriptor set: `buffers[i]` at binding `i` of set `set` of a layout, as the
/// layout's kind of that binding says (texel bindings get a view of the whole buffer).
pub struct DescriptorSet {
    layout: Arc<LayoutInner>,
    pool: vk::DescriptorPool,
    views: Vec<vk::BufferView>,
    pub(crate) raw: vk::DescriptorSet,
    pub(crate) set: u32,
}

impl DescriptorSet {
    pub fn new(layout: &BindingLayout, set: u32, buffers: &[&Buffer]) -> Result<DescriptorSet> {
        let inner = &layout.inner;
        let raw_dev = &inner.device.raw;
        let kinds = &inner.kinds[set as usize];
        if kinds.len() != buffers.len() {
            return Err(Error::BindingCount {
                set,
                expected: kinds.len(),
                got: buffers.len(),
            });
        }
        let count_of = |ty: vk::DescriptorType| {
            let n = kinds.iter().filter(|k| k.descriptor_type() == ty).count();
            n.max(1) as u32
        };
        let sizes = [
            vk::DescriptorType::STORAGE_BUFFER,
            vk::DescriptorType::STORAGE_TEXEL_BUFFER,
            vk::DescriptorType::UNIFORM_BUFFER,
        ]
        .map(|ty| {
            vk::DescriptorPoolSize::default()
                .ty(ty)
                .descriptor_count(count_of(ty))
        });
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: valid create info.
        let pool =
            unsafe { raw_dev.create_descriptor_pool(&info, None) }.vk("vkCreateDescriptorPool")?;
        let layouts = [inner.set_layouts[set as usize]];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        // SAFETY: pool sized for exactly this set.
        let raw = match unsafe { raw_dev.allocate_descriptor_sets(&alloc) } {
            Ok(s) => s[0],
            Err(result) => {
                // SAFETY: unused pool.
                unsafe { raw_dev.destroy_descriptor_pool(pool, None) };
                return Err(Error::Vk {
                    call: "vkAllocateDescriptorSets",
                    result,
                });
            }
        };
        let mut result = DescriptorSet {
            layout: inner.clone(),
            pool,
            views: Vec::new(),
            raw,
            set,
        };
        let mut views = vec![[vk::BufferView::null()]; buffers.len()];
        for (i, b) in buffers.iter().enumerate() {
            if let Some(format) = kinds[i].texel_format() {
                let info = vk::BufferViewCreateInfo::default()
                    .buffer(b.raw)
                    .format(format)
                    .offset(0)
                    .range(vk::WHOLE_SIZE);
                // SAFETY: a live buffer created with STORAGE_TEXEL_BUFFER usage; the view
                // is destroyed with the set (dropping `result` on error).
                let view =
                    unsafe { raw_dev.create_buffer_view(&info, None) }.vk("vkCreateBufferView")?;
                result.views.push(view);
                views[i] = [view];
            }
        }
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
            .iter()
            .map(|b| {
                [vk::DescriptorBufferInfo::default()
                    .buffer(b.raw)
                    .offset(0)
                    .range(vk::WHOLE_SIZE)]
            })
            .collect();
        let writes: Vec<_> = infos
            .iter()
            .enumerate()
            .map(|(i, info)| {
                let w = vk::WriteDescriptorSet::default()
                    .dst_set(raw)
                    .dst_binding(i as u32)
                    .descriptor_type(kinds[i].descriptor_type());
                match kinds[i].texel_format() {
                    None => w.buffer_info(info),
                    Some(_) => w.texel_buffer_view(&views[i]),
                }
            })
            .collect();
        // SAFETY: writes reference live buffers, views and this set.
        unsafe { raw_dev.update_descriptor_sets(&writes, &[]) };
        Ok(result)
    }
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        let raw = &self.layout.device.raw;
        // SAFETY: callers wait for GPU work before dropping sets it uses.
        unsafe {
            raw.destroy_descriptor_pool(self.pool, None);
            for &v in &self.views {
                raw.destroy_buffer_view(v, None);
            }
        };
    }
}

/// A compute pipeline made from SPIR-V with specialization constants.
pub struct Kernel {
    layout: Arc<LayoutInner>,
    pub(crate) pipeline: vk::Pipeline,
    name: String,
}

impl Kernel {
    /// `spec[i]` becomes specialization constant `constant_id = i` (32-bit each), and
    /// the layout's own constants ([`BindingLayout::with_spec`]) are added. On a layout
    /// for a split scene, a kernel that reads the scene runs its SCENE_SPLIT variant;
    /// on a device with [`DeviceInfo::int64`](super::DeviceInfo), a kernel that writes
    /// the wavefront's queues its WAVEFRONT_INT64 variant.
    pub fn new(
        device: &Device,
        name: &str,
        spirv: &[u8],
        layout: &BindingLayout,
        spec: &[u32],
    ) -> Result<Kernel> {
        Kernel::from_spec(device, layout, &KernelSpec::new(name, spirv, spec))
    }

    /// The kernel `spec` describes (see [`Kernel::new`]).
    pub fn from_spec(device: &Device, layout: &BindingLayout, spec: &KernelSpec) -> Result<Kernel> {
        let (name, spirv, inline) = (spec.name, spec.spirv, spec.inline);
        let spec = &spec.spec[..];
        let spirv = match layout.inner.scene {
            SceneAccess::Texels => spirv,
            SceneAccess::Split => super::shaders::scene_split_variant(spirv).unwrap_or(spirv),
            SceneAccess::Storage => super::shaders::scene_storage_variant(spirv).unwrap_or(spirv),
        };
        let spirv = match device.info().int64 {
            true => super::shaders::int64_variant(spirv).unwrap_or(spirv),
            false => spirv,
        };
        let code = ash::util::read_spv(&mut std::io::Cursor::new(spirv))
            .map_err(|_| Error::BadSpirv(name.into()))?;
        let shared = &layout.inner.spec;
        debug_assert!(
            shared
                .iter()
                .all(|&(id, _)| spec.iter().all(|&(k, _)| k != id)),
            "kernel '{name}': its specialization constants overlap the layout's"
        );
        let constants: Vec<(u32, u32)> = spec.iter().chain(shared.iter()).copied().collect();
        // The constants written into the module where spirv-opt can (see
        // `specialize`), else given to the driver.
        let specialized = super::specialize::specialize(name, &code, &constants, inline)?;
        let (code, constants) = match &specialized {
            Some(code) => (code, &[][..]),
            None => (&code, &constants[..]),
        };
        let raw = device.raw();
        let module_info = vk::ShaderModuleCreateInfo::default().code(code);
        // SAFETY: SPIR-V produced by glslang at build time (and specialized by spirv-opt).
        let module =
            unsafe { raw.create_shader_module(&module_info, None) }.vk("vkCreateShaderModule")?;
        let entries: Vec<_> = constants
            .iter()
            .enumerate()
            .map(|(i, &(id, _))| {
                vk::SpecializationMapEntry::default()
                    .constant_id(id)
                    .offset(4 * i as u32)
                    .size(4)
            })
            .collect();
        let values: Vec<u32> = constants.iter().map(|&(_, v)| v).collect();
        let data: &[u8] = bytemuck::cast_slice(&values);
        let spec_info = vk::SpecializationInfo::default()
            .map_entries(&entries)
            .data(data);
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(c"main")
            .specialization_info(&spec_info);
        let info = [vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout.inner.pipeline_layout)];
        // SAFETY: valid create info; module destroyed after pipeline creation.
        let result =
            unsafe { raw.create_compute_pipelines(device.inner.pipeline_cache, &info, None) };
        // SAFETY: the module is no longer needed once the pipeline exists.
        unsafe { raw.destroy_shader_module(module, None) };
        let pipeline = result.map_err(|(_, r)| r).vk("vkCreateComputePipelines")?[0];
        Ok(Kernel {
            layout: layout.inner.clone(),
            pipeline,
            name: name.into(),
        })
    }

    /// Creates the kernels `specs` describe (each as [`Kernel::new`]) on as many
    /// threads as the machine has cores, and returns them in order. On lavapipe
    /// creating a pipeline translates and optimizes its shader on the calling thread
    /// (Mesa's disk cache keeps only the machine code it compiles at the first
    /// dispatch), about 30 ms a kernel even when every cache is warm: one after the
    /// other they were most of a short render's start-up.
    pub fn new_all(
        device: &Device,
        layout: &BindingLayout,
        specs: &[KernelSpec],
    ) -> Result<Vec<Kernel>> {
        let threads = std::thread::available_parallelism()
            .map_or(1, |n| n.get())
            .min(specs.len())
            .max(1);
        let next = AtomicUsize::new(0);
        let mut made: Vec<Option<Result<Kernel>>> = specs.iter().map(|_| None).collect();
        std::thread::scope(|scope| {
            let workers: Vec<_> = (0..threads)
                .map(|_| {
                    scope.spawn(|| {
                        let mut done = Vec::new();
                        loop {
                            let i = next.fetch_add(1, Ordering::Relaxed);
                            let Some(s) = specs.get(i) else { break };
                            done.push((i, Kernel::from_spec(device, layout, s)));
                        }
                        done
                    })
                })
                .collect();
            for worker in workers {
                match worker.join() {
                    Ok(done) => done.into_iter().for_each(|(i, k)| made[i] = Some(k)),
                    Err(panic) => std::panic::resume_unwind(panic),
                }
            }
        });
        made.into_iter()
            .map(|k| k.unwrap_or_else(|| unreachable!("every index is taken once")))
            .collect()
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub(crate) fn pipeline_layout(&self) -> vk::PipelineLayout {
        self.layout.pipeline_layout
    }

    /// Records into `cmd` the binding of this kernel, `sets` and the push constants
    /// `push` (none where empty), ready for a dispatch.
    ///
    /// # Safety
    /// `cmd` is recording, and it and `sets` belong to this kernel's device.
    pub(crate) unsafe fn record_bind(
        &self,
        cmd: vk::CommandBuffer,
        sets: &[&DescriptorSet],
        push: &[u8],
    ) {
        let raw = &self.layout.device.raw;
        // SAFETY: as the caller promises.
        unsafe {
            raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            for s in sets {
                raw.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    self.pipeline_layout(),
                    s.set,
                    &[s.raw],
                    &[],
                );
            }
            if !push.is_empty() {
                raw.cmd_push_constants(
                    cmd,
                    self.pipeline_layout(),
                    vk::ShaderStageFlags::COMPUTE,
                    0,
                    push,
                );
            }
        }
    }
}

impl Drop for Kernel {
    fn drop(&mut self) {
        // SAFETY: callers wait for GPU work before dropping kernels.
        unsafe { self.layout.device.raw.destroy_pipeline(self.pipeline, None) };
    }
}
