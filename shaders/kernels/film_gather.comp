#version 460
#extension GL_GOOGLE_include_directive : require
// film_gather: adds to each crop pixel the filter-weighted samples of the pixels
// within the filter's reach, for every sample index whose last such pixel this batch
// rendered (so each sample of each pixel is gathered once, complete, whatever the
// batches). One thread per pixel of crop rows film_row .. film_row + film_rows.
// Per sample the neighbours are summed in row-major order and the sum added to the
// pixel's: the same additions in the same order for any batching or crop window, so
// a crop equals the window of the full render bit for bit. No atomics.
// With the box filter (FILM_FROM_PATHS) a sample weighs 1 in its own pixel and no
// other, so the pixel reads its samples' radiance from the batch's paths themselves:
// `accumulate` and the ring are skipped (a store and a load of every sample fewer),
// with the same additions in the same order. NaN and infinite samples are then
// counted here.
// Reads: the film's sample ring (or paths). Writes: the film's sums, counters.discarded.

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
#include "film/film.glsl"

// The filter (a FILTER_* value) and whether the film keeps alpha sums.
SPEC(FILM_FILTER);
SPEC(SCENE_FILM_ALPHA);
// Whether the pixels read their samples from the paths (the box filter; film.rs).
SPEC(FILM_FROM_PATHS);
#include "film/filter.glsl"

void main() {
    uint t = thread_index();
    uint cw = film.crop_width;
    if (t >= push.film_rows * cw) return;
    uvec2 qr = divide(t, cw);
    uvec2 c = uvec2(qr.y, push.film_row + qr.x);
    // This pixel and its neighbourhood in the sampled region's coordinates.
    int W = int(film.region_width);
    int P = W * int(film.region_height);
    ivec2 s = ivec2(film.crop_x + c.x, film.crop_y + c.y) - ivec2(film.region_x, film.region_y);
    int n = int(film.reach);
    ivec2 lo = max(s - n, ivec2(0));
    ivec2 hi = min(s + n, ivec2(W, int(film.region_height)) - 1);
    // The batch holds samples pixel_base .. pixel_base + path_count (counted over the
    // region's pixels, sample after sample, from sample sample_base); sample k (from
    // sample_base) of this pixel is complete once its last neighbour is among them.
    int last = hi.y * W + hi.x - int(push.pixel_base);
    int count = int(push.path_count);
    if (last >= count) return;
    int k_first = last >= 0 ? 0 : 1;
    int k_last = int(divide(uint(count - 1 - last), uint(P)).x);
    if (k_first > k_last) return;

    uint i = c.y * cw + c.x;
    vec4 sum = film_sums[i];
    float alpha = SCENE_FILM_ALPHA ? film_alpha_sums[i] : 0.0;
    if (FILM_FROM_PATHS) {
        // Sample k of this pixel is path k P + (its index - pixel_base) of the batch.
        int p = k_first * P + last;
        for (int k = k_first; k <= k_last; k++) {
            PathState path = path_load(uint(p));
            vec3 L = path.radiance;
            if (any(isnan(L)) || any(isinf(L))) {
                atomicAdd(counters.discarded, 1u);
            } else {
                sum += vec4(L, 1.0);
                if (SCENE_FILM_ALPHA && (path.flags & PATH_COVERED) != 0u) alpha += 1.0;
            }
            p += P;
        }
        film_sums[i] = sum;
        if (SCENE_FILM_ALPHA) film_alpha_sums[i] = alpha;
        return;
    }
    for (int k = k_first; k <= k_last; k++) {
        // The ring slot of the top-left neighbour in sample k: its path index (from
        // this batch's first; earlier batches' samples have negative indices and are
        // still in the ring) plus the first path's slot. Slots then advance along
        // rows without another division (llvmpipe divides lane by lane).
        uint row_slot = uint(k * P - int(push.pixel_base) + lo.y * W + lo.x
                             + int(push.sample_slot) + int(film.slots)) % film.slots;
        vec4 acc = vec4(0.0);
        float acc_alpha = 0.0;
        for (int y = lo.y; y <= hi.y; y++) {
            uint slot = row_slot;
            for (int x = lo.x; x <= hi.x; x++) {
                FilmSample fs = film_sample_load(slot);
                if ((fs.flags & FILM_SAMPLE_VALID) != 0u) {
                    // Pixel centre minus sample position, from the integer distance
                    // first: the same value whatever the region's origin.
                    float w = filter_weight(vec2(s - ivec2(x, y)) + 0.5 - fs.offset);
                    acc += w * vec4(fs.value, 1.0);
                    if (SCENE_FILM_ALPHA && (fs.flags & FILM_SAMPLE_COVERED) != 0u) acc_alpha += w;
                }
                slot = slot + 1u == film.slots ? 0u : slot + 1u;
            }
            row_slot += uint(W);
            if (row_slot >= film.slots) row_slot -= film.slots;
        }
        sum += acc;
        alpha += acc_alpha;
    }
    film_sums[i] = sum;
    if (SCENE_FILM_ALPHA) film_alpha_sums[i] = alpha;
}
