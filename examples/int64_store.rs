//! A reproduction of lavapipe's abort at 512 bits (Mesa 26.2.6, LLVM 22:
//! `*** stack smashing detected ***` inside libvulkan_lvp.so) for a Mesa bug report:
//! one dispatch of `shaders/tests/int64_store.comp`, which stores 16-byte words as two
//! 64-bit components, then a check of what it wrote.
//!
//!   cargo run --example int64_store -- [MODE] [COUNT]
//!
//! MODE (the kernel's specialization constant): 0 in-order 64-bit stores, 1 a divergent
//! scatter of them (default), 2 the same scatter through 32-bit components (the
//! control), 3 in-order 64-bit stores built without packUint2x32. tools/mesa_int64_store.sh runs every mode
//! under Debian sid's lavapipe at 256 and 512 bits.

use wavetrace::gpu::{
    shaders, BindingLayout, Buffer, CommandList, DescriptorSet, Device, Kernel, Location,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let mode: u32 = args.get(1).map_or(Ok(1), |s| s.parse())?;
    let count: u32 = args.get(2).map_or(Ok(4096), |s| s.parse())?;
    if count.is_multiple_of(7) {
        return Err(
            "COUNT must not be a multiple of 7 (the scatter i -> 7i mod COUNT must be one to one)"
                .into(),
        );
    }
    let device = Device::new(None)?;
    println!("device: {}, mode {mode}, {count} words", device.info().name);
    let layout = BindingLayout::new(&device, &[2], 4)?;
    let kernel = Kernel::new(
        &device,
        "int64_store",
        shaders::TESTS_INT64_STORE,
        &layout,
        &[mode],
    )?;
    let bytes = u64::from(count) * 16;
    let words64 = Buffer::new(&device, "words64", bytes, Location::Gpu)?;
    let words32 = Buffer::new(&device, "words32", bytes, Location::Gpu)?;
    let set = DescriptorSet::new(&layout, 0, &[&words64, &words32])?;
    let mut cmd = CommandList::new(&device)?;
    let push: [u32; 1] = [count];
    cmd.dispatch(
        &kernel,
        &[&set],
        bytemuck::bytes_of(&push),
        [count.div_ceil(64), 1, 1],
    );
    cmd.barrier();
    cmd.submit_and_wait()?;
    let written: Vec<[u32; 4]> = if mode == 2 {
        words32.read(&device)?
    } else {
        words64.read(&device)?
    };
    let wrong = (0..count)
        .filter(|&i| {
            let slot = if mode == 1 || mode == 2 {
                (i * 7) % count
            } else {
                i
            };
            let w = [i, i ^ 0x5555_5555, !i, i.wrapping_mul(2_654_435_761)];
            written[slot as usize] != w
        })
        .count();
    println!("{wrong} of {count} words wrong");
    if wrong > 0 {
        std::process::exit(1);
    }
    Ok(())
}
