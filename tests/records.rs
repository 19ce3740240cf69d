//! Every GPU record's generated GLSL loader and storer (generated/records.glsl, written by
//! build.rs from src/gpu/records.rs) against the Rust layout, on the device: records
//! whose every 4-byte word differs go through `T_LOAD` into a std430 block and through
//! `T_STORE` back to texels (shaders/tests/records.comp), and each field must come out
//! where Rust has it.

mod common;

use wavetrace::gpu::records::{Record, RECORDS};
use wavetrace::gpu::{
    shaders, BindingKind, BindingLayout, Buffer, CommandList, DescriptorSet, Kernel, Location,
};

/// The records the kernel round-trips: those of whole 16-byte texels (`RECORDS(X)`).
fn texel_records() -> Vec<&'static Record> {
    RECORDS.iter().filter(|r| r.size % 16 == 0).collect()
}

/// The mismatches between `got` and `want` (records 0 and 1 of each type, one type
/// after the other), named by record, index and field.
fn field_mismatches(records: &[&Record], want: &[u32], got: &[u32]) -> Vec<String> {
    let mut out = Vec::new();
    let mut base = 0;
    for r in records {
        for i in 0..2 {
            for f in r.fields {
                let first = base + (i * r.size + f.offset) / 4;
                let words = first..first + f.size / 4;
                if want[words.clone()] != got[words.clone()] {
                    out.push(format!(
                        "{}[{i}].{}: {:x?}, want {:x?}",
                        r.name,
                        f.name,
                        &got[words.clone()],
                        &want[words]
                    ));
                }
            }
        }
        base += 2 * r.size / 4;
    }
    out
}

#[test]
fn every_record_loader_agrees_with_its_rust_layout() {
    let records = texel_records();
    assert!(
        records.len() >= 14,
        "the scene, queue and photon records at least"
    );
    let words: usize = records.iter().map(|r| 2 * r.size / 4).sum();
    // A distinct normal float per word (1 + k 2^-23), so no float field can change it.
    let input: Vec<u32> = (0..words as u32).map(|k| 0x3f80_0000 + k).collect();
    let device = common::device();
    let layout = BindingLayout::with_kinds(
        &device,
        &[vec![
            BindingKind::Texels,
            BindingKind::Storage,
            BindingKind::Storage,
        ]],
        0,
    )
    .expect("binding layout");
    let kernel =
        Kernel::new(&device, "records", shaders::TESTS_RECORDS, &layout, &[]).expect("kernel");
    let texels = Buffer::texels(&device, "records", &input, 16).expect("input");
    let bytes = 4 * words as u64;
    let loaded = Buffer::new(&device, "loaded", bytes, Location::Gpu).expect("loaded");
    let stored = Buffer::new(&device, "stored", bytes, Location::Gpu).expect("stored");
    let set = DescriptorSet::new(&layout, 0, &[&texels, &loaded, &stored]).expect("set");
    let mut cmd = CommandList::new(&device).expect("command list");
    cmd.dispatch(&kernel, &[&set], &[], [1, 1, 1]);
    cmd.submit_and_wait().expect("records kernel");
    let loaded: Vec<u32> = loaded.read(&device).expect("read loaded");
    let stored: Vec<u32> = stored.read(&device).expect("read stored");
    let bad = field_mismatches(&records, &input, &loaded);
    assert!(bad.is_empty(), "loaded fields differ:\n{}", bad.join("\n"));
    let bad = field_mismatches(&records, &input, &stored);
    assert!(bad.is_empty(), "stored fields differ:\n{}", bad.join("\n"));
}
