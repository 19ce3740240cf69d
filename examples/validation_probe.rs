//! Proves that `WAVETRACE_VALIDATION=1` really validates: makes one forbidden Vulkan call
//! (`gpu::validation::provoke_error`), which the Khronos validation layer must report and
//! wavetrace must then abort on. `.ci/run` runs it before the suite's validation stage
//! and requires the abort; without validation it prints that nothing stopped it.

fn main() -> anyhow::Result<()> {
    let device = wavetrace::gpu::device::Device::new(None)?;
    wavetrace::gpu::validation::provoke_error(&device)?;
    println!("the invalid call went through: validation is off");
    Ok(())
}
