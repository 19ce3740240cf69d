#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: round-trips every GPU record through its generated loader and storer
// (generated/records.glsl, from src/gpu/records.rs), so tests/records.rs can check both
// field by field against the Rust layout.
//
// In: records 0 and 1 of each record type of RECORDS(X), one type after the other, as
// 16-byte texels (binding 0). Out: the loaded records as GLSL lays them out in a
// storage block (binding 1: std430, as the Rust structs), and stored again through
// the record's storer (binding 2: the input's texels).

#include "scene/layout.glsl"

layout(local_size_x = 1) in;

layout(set = 0, binding = 0, rgba32ui) uniform readonly uimageBuffer record_texels;
#define RECORD_OUT(T) T T##_out[2];
layout(std430, set = 0, binding = 1) writeonly buffer LoadedBuffer { RECORDS(RECORD_OUT) };
layout(std430, set = 0, binding = 2) writeonly buffer StoredBuffer { uvec4 stored_words[]; };

// The first texel of the current record type.
uint test_base;
uvec4 test_texel(uint k) { return imageLoad(record_texels, int(test_base + k)); }
void test_store(uint k, uvec4 w) { stored_words[test_base + k] = w; }
#define RECORD_ACCESS(T) T##_LOAD(T##_test_load, test_texel) T##_STORE(T##_test_store, test_store)
RECORDS(RECORD_ACCESS)

void main() {
    test_base = 0u;
#define RECORD_ROUND_TRIP(T)                    \
    for (uint i = 0u; i < 2u; i++) {           \
        T r = T##_test_load(i);                \
        T##_out[i] = r;                        \
        T##_test_store(i, r);                  \
    }                                          \
    test_base += 2u * T##_TEXELS;
    RECORDS(RECORD_ROUND_TRIP)
}
