// Descriptor set 2: the photon map and the photon mappers' per-pixel state. Bindings
// are mirrored in src/render/photon/mod.rs (`photon_binding_kinds`). As in
// wavefront.glsl, records written at scattered places are stored through 16-byte
// words and read through texel views of the same buffers (imageLoad, which llvmpipe
// gathers inline): use the *_load and *_store functions of record.glsl.
#ifndef PHOTON_BINDINGS_GLSL
#define PHOTON_BINDINGS_GLSL

#include "scene/layout.glsl"

layout(std140, set = 2, binding = 0) uniform PhotonParamsBuffer { PhotonParams photon_params; };
layout(std430, set = 2, binding = 1) buffer PhotonCounterBuffer { PhotonCounters photon_counters; };
// Photons as photon paths store them (appended), and sorted by grid bucket.
layout(std430, set = 2, binding = 2) writeonly buffer PhotonBuffer { uvec4 photon_words[]; };
layout(set = 2, binding = 3, rgba32ui) uniform readonly uimageBuffer photon_texels;
layout(std430, set = 2, binding = 4) writeonly buffer GridPhotonBuffer { uvec4 grid_photon_words[]; };
layout(set = 2, binding = 5, rgba32ui) uniform readonly uimageBuffer grid_photon_texels;
// The hash grid's buckets (grid.glsl): counts, then their prefix sums, then the first
// photon of each bucket; entry table_mask + 1 holds the total.
layout(std430, set = 2, binding = 6) buffer CellBuffer { uint cells[]; };
layout(set = 2, binding = 7, r32ui) uniform readonly uimageBuffer cell_words;
// Visible points: by path slot (photonmapper) or by pixel (sppm).
layout(std430, set = 2, binding = 8) writeonly buffer VisiblePointBuffer { uvec4 vp_words[]; };
layout(set = 2, binding = 9, rgba32ui) uniform readonly uimageBuffer vp_texels;
layout(std430, set = 2, binding = 10) buffer SppmPixelBuffer { SppmPixel sppm_pixels[]; };
// Block sums of the bucket prefix sum (photon_grid_scan.comp).
layout(std430, set = 2, binding = 11) buffer ScanBuffer { uint scan_sums[]; };
// The particle tracer's splats of one sample index (integrator/ptracer.glsl): per
// pixel of the film, three channels of 64-bit fixed point as (low, high) words.
layout(std430, set = 2, binding = 12) buffer SplatBuffer { uint splat_words[]; };

#endif
