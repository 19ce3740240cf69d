//! Instance, physical-device choice, logical device, queue and pipeline cache.

use std::ffi::CStr;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use super::error::{Error, Result, VkContext};
use super::validation;

/// What kind of device this is, best first when choosing by default.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum DeviceKind {
    Discrete,
    Integrated,
    Virtual,
    Other,
    Cpu,
}

impl DeviceKind {
    fn from_vk(t: vk::PhysicalDeviceType) -> Self {
        match t {
            vk::PhysicalDeviceType::DISCRETE_GPU => Self::Discrete,
            vk::PhysicalDeviceType::INTEGRATED_GPU => Self::Integrated,
            vk::PhysicalDeviceType::VIRTUAL_GPU => Self::Virtual,
            vk::PhysicalDeviceType::CPU => Self::Cpu,
            _ => Self::Other,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Discrete => "discrete GPU",
            Self::Integrated => "integrated GPU",
            Self::Virtual => "virtual GPU",
            Self::Other => "other",
            Self::Cpu => "CPU",
        }
    }
}

/// Facts about the chosen device, for printing and for limits.
#[derive(Debug, Clone)]
pub struct DeviceInfo {
    pub index: usize,
    pub name: String,
    pub kind: DeviceKind,
    pub driver: String,
    pub vendor_id: u32,
    pub device_id: u32,
    /// Nanoseconds per timestamp tick; `None` if the queue has no timestamps.
    pub timestamp_period_ns: Option<f64>,
    /// Largest storage-buffer binding (`maxStorageBufferRange`): bounds the wavefront's
    /// queues and film, which kernels write.
    pub max_storage_buffer_range: u64,
    /// Most texels one texel-buffer view addresses (`maxTexelBufferElements`): with
    /// [`DeviceInfo::max_memory_allocation_size`], bounds one part of a scene array
    /// (`render::scene_parts`).
    pub max_texel_buffer_elements: u64,
    /// Largest single memory allocation (`maxMemoryAllocationSize`, Vulkan 1.1).
    pub max_memory_allocation_size: u64,
    /// Memory the device can hold, bytes: the largest device-local heap (on a CPU
    /// device, at least 3/4 of the host's RAM; see `device_memory`).
    pub device_memory: u64,
    pub max_workgroups_x: u32,
    /// Whether kernels run their `WAVEFRONT_INT64` variants (64-bit stores of the
    /// wavefront's queues, `shaders::int64_variant`): the device has shaderInt64,
    /// the driver compiles them ([`int64_stores_work`]), and the environment variable
    /// `WAVETRACE_NO_INT64` is not set (it forces the 32-bit variants, which every
    /// device runs).
    pub int64: bool,
    /// Whether kernels read the scene from storage buffers
    /// ([`SceneAccess::Storage`](super::SceneAccess)) where the layout and the scene
    /// allow it ([`DeviceInfo::max_storage_buffers`], `max_storage_buffer_range`): the
    /// driver reads them faster ([`scene_storage_faster`]) and the environment variable
    /// `WAVETRACE_SCENE_TEXELS` is not set (it forces texel buffers, which every device
    /// runs).
    pub scene_storage: bool,
    /// Whether shade and shadow in scenes with null surfaces pay for leaving the rays
    /// that must trace again to full twins of themselves (shaders/queue/deferral.glsl;
    /// [`deferral_pays`]): every driver but lavapipe of Mesa 26 or later.
    pub deferral_pays: bool,
    /// Whether subgroup s of a workgroup holds the workgroup's invocations
    /// s × subgroup size onwards, in order (llvmpipe: a subgroup is one SIMD vector of
    /// consecutive invocations), so that the kernels' `thread_index` is read from the
    /// subgroup's number and the lane's (the `SUBGROUPS_IN_ORDER` specialization
    /// constant) instead of `gl_LocalInvocationID`, which llvmpipe computes with an
    /// integer division per lane. Vulkan promises no such order, so other devices keep
    /// `gl_LocalInvocationID`.
    pub subgroups_in_order: bool,
    /// Storage buffers one kernel may bind (`maxPerStageDescriptorStorageBuffers`, and
    /// `maxDescriptorSetStorageBuffers`, the lesser).
    pub max_storage_buffers: u32,
    /// Time to load Vulkan, create the instance and the device.
    pub startup_seconds: f64,
}

impl std::fmt::Display for DeviceInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "[{}] {} ({}, {})",
            self.index,
            self.name,
            self.kind.name(),
            self.driver
        )
    }
}

/// The window surface a device was opened to present to ([`Device::with_surface`]),
/// destroyed with the device.
pub(crate) struct Surface {
    pub loader: ash::khr::surface::Instance,
    pub raw: vk::SurfaceKHR,
}

/// What a device must do besides compute to show images in a window: the instance
/// extensions the window system needs, and a function that makes the window's
/// surface on the instance (raw `VkInstance` handle in, raw `VkSurfaceKHR` out, or why
/// not). The chosen device's compute queue must be able to present to that surface.
pub struct SurfaceRequest<'a> {
    pub instance_extensions: &'a [String],
    pub create: &'a mut dyn FnMut(u64) -> std::result::Result<u64, String>,
}

pub(crate) struct Inner {
    _entry: ash::Entry,
    pub instance: ash::Instance,
    /// The window surface the queue presents to, if the device was opened for one.
    pub surface: Option<Surface>,
    pub physical: vk::PhysicalDevice,
    pub raw: ash::Device,
    pub queue: vk::Queue,
    pub command_pool: vk::CommandPool,
    pub memory: vk::PhysicalDeviceMemoryProperties,
    pub pipeline_cache: vk::PipelineCache,
    pipeline_cache_path: Option<PathBuf>,
    pub info: DeviceInfo,
    /// The validation layer's messenger ([`validation`]), when asked for.
    messenger: Option<validation::Messenger>,
}

/// A Vulkan device with one compute queue. Cheap to clone.
#[derive(Clone)]
pub struct Device {
    pub(crate) inner: Arc<Inner>,
}

/// A device that can be chosen, as listed by [`Device::list`].
#[derive(Debug, Clone)]
pub struct Candidate {
    pub index: usize,
    pub name: String,
    pub kind: DeviceKind,
}

fn load_entry() -> Result<ash::Entry> {
    // SAFETY: loading the system Vulkan loader; no other Vulkan state exists yet.
    unsafe { ash::Entry::load() }.map_err(|e| Error::LoaderMissing(e.to_string()))
}

fn create_instance(entry: &ash::Entry, extensions: &[String]) -> Result<ash::Instance> {
    let app = vk::ApplicationInfo::default()
        .application_name(c"wavetrace")
        .engine_name(c"wavetrace")
        .api_version(vk::API_VERSION_1_2);
    let names: Vec<std::ffi::CString> = extensions
        .iter()
        .filter_map(|e| std::ffi::CString::new(e.as_str()).ok())
        .collect();
    let mut pointers: Vec<*const std::ffi::c_char> = names.iter().map(|n| n.as_ptr()).collect();
    let mut layers: Vec<*const std::ffi::c_char> = Vec::new();
    let enables = validation::features();
    let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
    let validate = validation::requested();
    if validate {
        let (names, extension) = validation::instance_needs(entry)?;
        layers.extend(names.iter().map(|n| n.as_ptr()));
        pointers.push(extension.as_ptr());
    }
    let mut info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_extension_names(&pointers)
        .enabled_layer_names(&layers);
    if validate {
        info = info.push_next(&mut features);
    }
    // SAFETY: valid create info; the instance is destroyed in Inner::drop.
    unsafe { entry.create_instance(&info, None) }.map_err(|result| match result {
        vk::Result::ERROR_INCOMPATIBLE_DRIVER => Error::NoDevice,
        vk::Result::ERROR_EXTENSION_NOT_PRESENT => Error::NoPresentation(format!(
            "the Vulkan loader lacks the window-system extensions {}",
            extensions.join(", ")
        )),
        result => Error::Vk {
            call: "vkCreateInstance",
            result,
        },
    })
}

struct Physical {
    handle: vk::PhysicalDevice,
    name: String,
    kind: DeviceKind,
    queue_family: u32,
}

fn enumerate(instance: &ash::Instance) -> Result<Vec<Physical>> {
    // SAFETY: instance is valid.
    let devices =
        unsafe { instance.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    let mut out = Vec::new();
    for handle in devices {
        // SAFETY: handle comes from the instance.
        let props = unsafe { instance.get_physical_device_properties(handle) };
        let name = props
            .device_name_as_c_str()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|_| "unnamed device".into());
        // SAFETY: as above.
        let families = unsafe { instance.get_physical_device_queue_family_properties(handle) };
        let Some(queue_family) = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::COMPUTE))
        else {
            continue;
        };
        if props.api_version < vk::API_VERSION_1_2 {
            continue;
        }
        out.push(Physical {
            handle,
            name,
            kind: DeviceKind::from_vk(props.device_type),
            queue_family: queue_family as u32,
        });
    }
    Ok(out)
}

fn pick(devices: &[Physical], selector: Option<&str>) -> Result<usize> {
    if devices.is_empty() {
        return Err(Error::NoDevice);
    }
    let Some(selector) = selector else {
        // Best kind first (discrete before integrated before CPU); ties keep order.
        return Ok((0..devices.len())
            .min_by_key(|&i| devices[i].kind)
            .unwrap_or(0));
    };
    let found = match selector.parse::<usize>() {
        Ok(i) if i < devices.len() => Some(i),
        _ => {
            let s = selector.to_lowercase();
            devices.iter().position(|d| {
                d.name.to_lowercase().contains(&s) || d.kind.name().to_lowercase().contains(&s)
            })
        }
    };
    found.ok_or_else(|| Error::DeviceNotFound {
        selector: selector.to_string(),
        available: devices
            .iter()
            .enumerate()
            .map(|(i, d)| format!("  [{i}] {} ({})", d.name, d.kind.name()))
            .collect::<Vec<_>>()
            .join("\n"),
    })
}

/// The device to present to `surface` with, as [`pick`] chooses among those that can
/// (each one's `queue_family` becomes one that computes and presents); a selected
/// device that cannot present, or none that can, is an error.
fn pick_presenting(
    instance: &ash::Instance,
    devices: &mut [Physical],
    selector: Option<&str>,
    surface: &Surface,
) -> Result<usize> {
    let mut presenting = Vec::new();
    for (i, d) in devices.iter_mut().enumerate() {
        // SAFETY: handle comes from the instance.
        let families = unsafe { instance.get_physical_device_queue_family_properties(d.handle) };
        // SAFETY: device handle and surface come from this instance.
        let has_swapchain = unsafe { instance.enumerate_device_extension_properties(d.handle) }
            .map(|exts| {
                exts.iter().any(|e| {
                    e.extension_name_as_c_str()
                        .is_ok_and(|n| n == ash::khr::swapchain::NAME)
                })
            })
            .unwrap_or(false);
        let family = (0..families.len() as u32).find(|&f| {
            families[f as usize]
                .queue_flags
                .contains(vk::QueueFlags::COMPUTE)
                // SAFETY: as above.
                && unsafe {
                    surface
                        .loader
                        .get_physical_device_surface_support(d.handle, f, surface.raw)
                }
                .unwrap_or(false)
        });
        if let (Some(f), true) = (family, has_swapchain) {
            d.queue_family = f;
            presenting.push(i);
        }
    }
    let names = |list: &mut dyn Iterator<Item = usize>| {
        list.map(|i| format!("  [{i}] {} ({})", devices[i].name, devices[i].kind.name()))
            .collect::<Vec<_>>()
            .join("\n")
    };
    if selector.is_some() {
        let index = pick(devices, selector)?;
        if presenting.contains(&index) {
            return Ok(index);
        }
        return Err(Error::NoPresentation(format!(
            "device [{index}] {} cannot present to this window; devices that can:\n{}",
            devices[index].name,
            if presenting.is_empty() {
                "  (none)".to_string()
            } else {
                names(&mut presenting.iter().copied())
            }
        )));
    }
    presenting
        .iter()
        .copied()
        .min_by_key(|&i| devices[i].kind)
        .ok_or_else(|| {
            Error::NoPresentation(format!(
                "no Vulkan device can present to this window (devices:\n{})",
                names(&mut (0..devices.len()))
            ))
        })
}

/// Size of the largest device-local heap (any heap if none is device-local).
fn largest_device_heap(memory: &vk::PhysicalDeviceMemoryProperties) -> u64 {
    let heaps = &memory.memory_heaps[..memory.memory_heap_count as usize];
    let local = heaps
        .iter()
        .filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
        .map(|h| h.size)
        .max();
    local
        .or_else(|| heaps.iter().map(|h| h.size).max())
        .unwrap_or(0)
}

/// The memory a device can hold: its largest heap, except on a CPU device, whose
/// memory is the host's: there at least 3/4 of the host's RAM (what lavapipe reports
/// since Mesa 23; Mesa 22.3's lavapipe reports a fixed 2 GiB heap that it does not
/// enforce, which would refuse scenes the machine holds easily).
fn device_memory(kind: DeviceKind, heap: u64) -> u64 {
    if kind != DeviceKind::Cpu {
        return heap;
    }
    heap.max(host_memory().map_or(0, |total| total / 4 * 3))
}

/// The host's physical memory, bytes (`MemTotal` of /proc/meminfo; Linux only).
fn host_memory() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line["MemTotal:".len()..]
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib * 1024)
}

pub(crate) fn cache_dir() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("XDG_CACHE_HOME") {
        return Some(PathBuf::from(dir).join("wavetrace"));
    }
    std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache").join("wavetrace"))
}

impl Device {
    /// Lists the devices that could run wavetrace.
    pub fn list() -> Result<Vec<Candidate>> {
        let entry = load_entry()?;
        let instance = create_instance(&entry, &[])?;
        let list = enumerate(&instance).map(|devices| {
            devices
                .into_iter()
                .enumerate()
                .map(|(index, d)| Candidate {
                    index,
                    name: d.name,
                    kind: d.kind,
                })
                .collect()
        });
        // SAFETY: nothing else uses this instance.
        unsafe { instance.destroy_instance(None) };
        list
    }

    /// Opens a device: the one `selector` names (index or part of its name), else
    /// the best available (a discrete GPU before an integrated one before lavapipe).
    pub fn new(selector: Option<&str>) -> Result<Device> {
        Self::create(selector, None)
    }

    /// Opens a device as [`Device::new`] does, one whose compute queue can also
    /// present to the window surface `request` makes (the viewer's): without a
    /// selector the best such device, with one the named device, which must present.
    pub fn with_surface(selector: Option<&str>, request: SurfaceRequest) -> Result<Device> {
        Self::create(selector, Some(request))
    }

    fn create(selector: Option<&str>, request: Option<SurfaceRequest>) -> Result<Device> {
        let start = Instant::now();
        let entry = load_entry()?;
        let extensions = request.as_ref().map_or(&[][..], |r| r.instance_extensions);
        let instance = create_instance(&entry, extensions)?;
        let surface = match request {
            None => None,
            Some(r) => {
                let raw = vk::Handle::as_raw(instance.handle());
                match (r.create)(raw) {
                    Ok(s) => Some(Surface {
                        loader: ash::khr::surface::Instance::new(&entry, &instance),
                        raw: vk::Handle::from_raw(s),
                    }),
                    Err(message) => {
                        // SAFETY: nothing was created from the instance.
                        unsafe { instance.destroy_instance(None) };
                        return Err(Error::NoPresentation(message));
                    }
                }
            }
        };
        let messenger = if validation::requested() {
            match validation::Messenger::new(&entry, &instance) {
                Ok(m) => Some(m),
                Err(e) => {
                    // SAFETY: nothing was created from the instance but the surface.
                    unsafe {
                        if let Some(s) = surface {
                            s.loader.destroy_surface(s.raw, None);
                        }
                        instance.destroy_instance(None)
                    };
                    return Err(e);
                }
            }
        } else {
            None
        };
        let opened = Self::open(&entry, &instance, selector, surface.as_ref(), start);
        match opened {
            Ok(mut inner) => {
                inner.surface = surface;
                inner.messenger = messenger;
                Ok(Device {
                    inner: Arc::new(inner),
                })
            }
            Err(e) => {
                // SAFETY: nothing was created from the instance that still lives but
                // the surface, destroyed first.
                unsafe {
                    if let Some(s) = surface {
                        s.loader.destroy_surface(s.raw, None);
                    }
                    if let Some(m) = messenger {
                        m.destroy();
                    }
                    instance.destroy_instance(None)
                };
                Err(e)
            }
        }
    }

    // Everything after the instance. On error the caller destroys the instance; on
    // success the returned Inner owns it (its Drop destroys it).
    fn open(
        entry: &ash::Entry,
        instance: &ash::Instance,
        selector: Option<&str>,
        surface: Option<&Surface>,
        start: Instant,
    ) -> Result<Inner> {
        let mut devices = enumerate(instance)?;
        let index = match surface {
            None => pick(&devices, selector)?,
            Some(s) => pick_presenting(instance, &mut devices, selector, s)?,
        };
        let phys = &devices[index];
        // SAFETY: physical device from this instance.
        let props = unsafe { instance.get_physical_device_properties(phys.handle) };
        let mut driver_props = vk::PhysicalDeviceDriverProperties::default();
        let mut maintenance3 = vk::PhysicalDeviceMaintenance3Properties::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default()
            .push_next(&mut driver_props)
            .push_next(&mut maintenance3);
        // SAFETY: as above; Vulkan 1.2 core.
        unsafe { instance.get_physical_device_properties2(phys.handle, &mut props2) };
        let driver = driver_props
            .driver_name_as_c_str()
            .map(CStr::to_string_lossy)
            .unwrap_or_default()
            .into_owned();
        let driver_info = driver_props
            .driver_info_as_c_str()
            .map(CStr::to_string_lossy)
            .unwrap_or_default()
            .into_owned();
        // SAFETY: as above.
        let families = unsafe { instance.get_physical_device_queue_family_properties(phys.handle) };
        let ts_bits = families[phys.queue_family as usize].timestamp_valid_bits;
        let timestamp_period_ns = (ts_bits > 0 && props.limits.timestamp_compute_and_graphics != 0)
            .then_some(props.limits.timestamp_period as f64);

        let priorities = [1.0f32];
        let queue_info = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(phys.queue_family)
            .queue_priorities(&priorities)];
        let swapchain_extension = [ash::khr::swapchain::NAME.as_ptr()];
        // SAFETY: physical device from this instance.
        let supported = unsafe { instance.get_physical_device_features(phys.handle) };
        let int64 = supported.shader_int64 == vk::TRUE
            && int64_stores_work(&phys.name)
            && std::env::var_os("WAVETRACE_NO_INT64").is_none();
        let features = vk::PhysicalDeviceFeatures::default().shader_int64(int64);
        let mut device_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_info)
            .enabled_features(&features);
        if surface.is_some() {
            device_info = device_info.enabled_extension_names(&swapchain_extension);
        }
        // SAFETY: valid create info for this physical device.
        let raw = unsafe { instance.create_device(phys.handle, &device_info, None) }
            .vk("vkCreateDevice")?;
        // SAFETY: queue family and index exist by construction.
        let queue = unsafe { raw.get_device_queue(phys.queue_family, 0) };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(phys.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device.
        let command_pool = match unsafe { raw.create_command_pool(&pool_info, None) } {
            Ok(p) => p,
            Err(result) => {
                // SAFETY: nothing was created from the device.
                unsafe { raw.destroy_device(None) };
                return Err(Error::Vk {
                    call: "vkCreateCommandPool",
                    result,
                });
            }
        };
        // SAFETY: valid physical device.
        let memory = unsafe { instance.get_physical_device_memory_properties(phys.handle) };

        // A pipeline cache on disk spares real GPUs the shader compile on later runs
        // (llvmpipe keeps its own cache in Mesa's shader disk cache).
        let pipeline_cache_path = cache_dir().map(|d| {
            d.join(format!(
                "pipelines-{:04x}-{:04x}-{:08x}.bin",
                props.vendor_id, props.device_id, props.driver_version
            ))
        });
        let initial = pipeline_cache_path
            .as_ref()
            .and_then(|p| std::fs::read(p).ok())
            .unwrap_or_default();
        let cache_info = vk::PipelineCacheCreateInfo::default().initial_data(&initial);
        // SAFETY: the driver validates the header of the initial data and ignores
        // data from another device or driver.
        let pipeline_cache = unsafe { raw.create_pipeline_cache(&cache_info, None) }
            .or_else(|_| {
                // SAFETY: as above, without initial data.
                unsafe { raw.create_pipeline_cache(&vk::PipelineCacheCreateInfo::default(), None) }
            })
            .vk("vkCreatePipelineCache")?;

        let subgroups_in_order = driver == "llvmpipe";
        let scene_storage = scene_storage_faster(&driver, &driver_info)
            && std::env::var_os("WAVETRACE_SCENE_TEXELS").is_none();
        let deferral_pays = deferral_pays(&driver, &driver_info);
        let info = DeviceInfo {
            index,
            name: phys.name.clone(),
            kind: phys.kind,
            driver,
            vendor_id: props.vendor_id,
            device_id: props.device_id,
            timestamp_period_ns,
            max_storage_buffer_range: props.limits.max_storage_buffer_range as u64,
            max_texel_buffer_elements: props.limits.max_texel_buffer_elements as u64,
            max_memory_allocation_size: maintenance3.max_memory_allocation_size,
            device_memory: device_memory(phys.kind, largest_device_heap(&memory)),
            max_workgroups_x: props.limits.max_compute_work_group_count[0],
            int64,
            scene_storage,
            deferral_pays,
            subgroups_in_order,
            max_storage_buffers: props
                .limits
                .max_per_stage_descriptor_storage_buffers
                .min(props.limits.max_descriptor_set_storage_buffers),
            startup_seconds: start.elapsed().as_secs_f64(),
        };
        Ok(Inner {
            _entry: entry.clone(),
            instance: instance.clone(),
            surface: None,
            physical: phys.handle,
            raw,
            queue,
            command_pool,
            memory,
            pipeline_cache,
            pipeline_cache_path,
            info,
            messenger: None,
        })
    }

    pub fn info(&self) -> &DeviceInfo {
        &self.inner.info
    }

    pub(crate) fn raw(&self) -> &ash::Device {
        &self.inner.raw
    }

    /// Writes the pipeline cache to disk so the next run skips shader compilation
    /// on drivers that honour it. Failures only cost time, so they are ignored.
    pub fn save_pipeline_cache(&self) {
        let Some(path) = &self.inner.pipeline_cache_path else {
            return;
        };
        // SAFETY: valid cache of this device.
        if let Ok(data) = unsafe {
            self.inner
                .raw
                .get_pipeline_cache_data(self.inner.pipeline_cache)
        } {
            // Several processes (tests, split renders) save the same cache: one shared
            // temporary name let one rename the other's half-written file into place.
            super::specialize::store_cache_file(path, &data);
        }
    }

    /// Index of a memory type with `wanted` flags among those `type_bits` allows.
    pub(crate) fn memory_type(
        &self,
        type_bits: u32,
        wanted: vk::MemoryPropertyFlags,
    ) -> Option<u32> {
        let mem = &self.inner.memory;
        (0..mem.memory_type_count).find(|&i| {
            type_bits & (1 << i) != 0
                && mem.memory_types[i as usize].property_flags.contains(wanted)
        })
    }

    pub(crate) fn memory_flags(&self, index: u32) -> vk::MemoryPropertyFlags {
        self.inner.memory.memory_types[index as usize].property_flags
    }
}

impl Drop for Inner {
    fn drop(&mut self) {
        // SAFETY: every object made from this device holds an Arc<Inner>, so all
        // of them are gone; wait for the queue before destroying.
        unsafe {
            let _ = self.raw.device_wait_idle();
            self.raw.destroy_pipeline_cache(self.pipeline_cache, None);
            self.raw.destroy_command_pool(self.command_pool, None);
            self.raw.destroy_device(None);
            if let Some(s) = &self.surface {
                s.loader.destroy_surface(s.raw, None);
            }
            if let Some(m) = &self.messenger {
                m.destroy();
            }
            self.instance.destroy_instance(None);
        }
    }
}

#[cfg(test)]
impl DeviceInfo {
    /// lavapipe's capabilities (Mesa 22.3.6 on a 24 GiB host), for tests that plan a
    /// render without a device.
    pub(crate) fn lavapipe_for_tests() -> DeviceInfo {
        DeviceInfo {
            index: 0,
            name: "llvmpipe".into(),
            kind: DeviceKind::Cpu,
            driver: "llvmpipe".into(),
            vendor_id: 0,
            device_id: 0,
            timestamp_period_ns: None,
            max_storage_buffer_range: 128 << 20,
            max_texel_buffer_elements: 1 << 27,
            max_memory_allocation_size: 2 << 30,
            device_memory: 24 << 30,
            max_workgroups_x: 65535,
            int64: true,
            scene_storage: false,
            deferral_pays: true,
            subgroups_in_order: true,
            max_storage_buffers: 8,
            startup_seconds: 0.0,
        }
    }
}

/// The SIMD width llvmpipe names in its device name, "llvmpipe (LLVM 22.1.8, 512
/// bits)"; `None` for any other device.
pub fn llvmpipe_bits(name: &str) -> Option<u32> {
    let rest = name.strip_prefix("llvmpipe")?;
    let bits = rest.split(" bits").next()?.rsplit([' ', ',', '(']).next()?;
    bits.parse().ok()
}

/// Whether the kernels' 64-bit queue stores (`WAVEFRONT_INT64`) compile on the device
/// named `name`: llvmpipe wider than 256 bits (`LP_NATIVE_VECTOR_WIDTH=512`; Mesa
/// 26.2.6 with LLVM 22) aborts inside the driver on them (`*** stack smashing detected
/// ***`; reproduced alone by `examples/int64_store.rs`, tools/mesa_int64_store.sh), so
/// there the 32-bit stores run, which render the same image bit for bit.
pub fn int64_stores_work(name: &str) -> bool {
    llvmpipe_bits(name).is_none_or(|bits| bits <= 256)
}

/// Whether kernels read the scene faster from storage buffers than through texel
/// buffers on the driver `driver` (VkPhysicalDeviceDriverProperties' name) whose
/// `driverInfo` is `info`: lavapipe of Mesa 26 or later, which compiles every image
/// load into a call of a separately compiled function (its live SIMD registers saved
/// around it) and a storage-buffer load at scattered addresses into an inline gather
/// (one load where every lane reads one address). Measured on Mesa 26.2.6 at 512 bits
/// (docs/performance.md): the Cornell box 6% faster, the normal-map scene 17%. Mesa
/// 22.3 gathers image loads inline and loops over the lanes for a storage buffer (and
/// a render that bound the scene's 31 storage buffers there segfaulted; the cause was
/// not looked into). Other drivers keep texel buffers.
pub fn scene_storage_faster(driver: &str, info: &str) -> bool {
    lavapipe_mesa_major(driver, info).is_some_and(|m| m >= 26)
}

/// Whether deferral (shaders/queue/deferral.glsl) pays on the driver `driver` whose
/// `driverInfo` is `info`. It was made for Mesa 22.3's lavapipe, which runs a crossing
/// loop's traversal for every SIMD group at every crossing whether a lane traces or
/// not (Debian's 22.3.6, the HG media cube at 256², 64 spp: 1.66 s deferring, 1.70 s
/// not). Mesa 26's does not pay it (26.2.6 at 512 bits, medians of 5-7 alternated:
/// the HG cube 0.559 s deferring, 0.546 s not; the isotropic cube 0.563 against 0.547;
/// thin_textured 0.481 against 0.485), and the two extra dispatches of each bounce
/// are two more points where lavapipe's threads sleep and wake (docs/performance.md).
/// GPUs keep it: tracing in a loop diverges there too.
pub fn deferral_pays(driver: &str, info: &str) -> bool {
    lavapipe_mesa_major(driver, info).is_none_or(|m| m < 26)
}

/// The Mesa major version of lavapipe (`driver` "llvmpipe", `info` its driverInfo,
/// "Mesa 26.2.6-1 (LLVM 22.1.8)"); None for another driver or an unreadable version.
fn lavapipe_mesa_major(driver: &str, info: &str) -> Option<u32> {
    if driver != "llvmpipe" {
        return None;
    }
    info.strip_prefix("Mesa ")
        .and_then(|v| v.split('.').next())
        .and_then(|m| m.parse::<u32>().ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deferral_but_on_lavapipe_from_mesa_26() {
        assert!(!deferral_pays("llvmpipe", "Mesa 26.2.6-1 (LLVM 22.1.8)"));
        assert!(!deferral_pays(
            "llvmpipe",
            "Mesa 27.0.0-devel (git-1234abcd)"
        ));
        assert!(deferral_pays("llvmpipe", "Mesa 22.3.6 (LLVM 15.0.6)"));
        assert!(deferral_pays("llvmpipe", ""));
        assert!(deferral_pays("radv", "Mesa 26.2.6"));
    }

    #[test]
    fn scene_storage_on_lavapipe_from_mesa_26() {
        assert!(scene_storage_faster(
            "llvmpipe",
            "Mesa 26.2.6-1 (LLVM 22.1.8)"
        ));
        assert!(scene_storage_faster(
            "llvmpipe",
            "Mesa 27.0.0-devel (git-1234abcd) (LLVM 22.1.8)"
        ));
        assert!(!scene_storage_faster(
            "llvmpipe",
            "Mesa 22.3.6 (LLVM 15.0.6)"
        ));
        assert!(!scene_storage_faster("llvmpipe", ""));
        assert!(!scene_storage_faster("radv", "Mesa 26.2.6"));
    }

    #[test]
    fn wide_llvmpipe_runs_32_bit_stores() {
        assert_eq!(llvmpipe_bits("llvmpipe (LLVM 15.0.6, 256 bits)"), Some(256));
        assert_eq!(llvmpipe_bits("llvmpipe (LLVM 22.1.8, 512 bits)"), Some(512));
        assert_eq!(llvmpipe_bits("NVIDIA H100 80GB HBM3"), None);
        assert!(int64_stores_work("llvmpipe (LLVM 15.0.6, 256 bits)"));
        assert!(!int64_stores_work("llvmpipe (LLVM 22.1.8, 512 bits)"));
        assert!(int64_stores_work("AMD Radeon RX 7900 XTX (RADV NAVI31)"));
    }

    /// A GPU's memory is its heap; a CPU device's is the host's where that is larger
    /// (lavapipe's fixed 2 GiB heap must not refuse what the host holds).
    #[test]
    fn cpu_devices_hold_what_the_host_holds() {
        let heap = 2u64 << 30;
        assert_eq!(device_memory(DeviceKind::Discrete, heap), heap);
        let cpu = device_memory(DeviceKind::Cpu, heap);
        assert!(cpu >= heap);
        if let Some(total) = host_memory() {
            assert!(total > 0);
            assert_eq!(cpu, heap.max(total / 4 * 3));
        }
    }
}
