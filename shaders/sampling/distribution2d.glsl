// Piecewise-constant 2-D distributions over a w x h grid of cells covering [0, 1]²
// (PBR 3rd ed., sec. 13.6.7): the marginal CDF over rows picks the row, the row's
// conditional CDF the column, and the point is uniform in the cell. Layout in the
// distribution buffer (dist_value) from `base`: h + 1 marginal values, then w + 1 per
// row. Built by src/scene/distribution2d.rs (the CPU reference). Environment maps
// (envmap.glsl) and textured area emitters (emitter_texture.glsl) sample by one.
// Needs scene_bindings.glsl.
#ifndef DISTRIBUTION2D_GLSL
#define DISTRIBUTION2D_GLSL

// Index k in [0, n) with cdf[k] <= x < cdf[k + 1] for the n + 1 values from
// dist_value(base) (the last k whose cdf[k] <= x: never a zero-probability entry).
uint dist2d_find(uint base, uint n, float x) {
    uint lo = 0u, hi = n; // invariant: cdf[lo] <= x, answer < hi
    while (lo + 1u < hi) {
        uint mid = (lo + hi) >> 1u;
        if (dist_value(base + mid) <= x) lo = mid; else hi = mid;
    }
    return lo;
}

// Probability of cell (i, j) times w h: the density p(u, v) there (per unit area of
// [0, 1]²).
float dist2d_cell_density(uint base, uint w, uint h, uint i, uint j) {
    uint row = base + h + 1u + j * (w + 1u);
    float pm = dist_value(base + j + 1u) - dist_value(base + j);
    float pc = dist_value(row + i + 1u) - dist_value(row + i);
    return pm * pc * float(w * h);
}

// The cell that u picks (u.x the row, u.y the column) and u's position within it,
// each coordinate in [0, 1] (x along the row).
void dist2d_sample_cell(uint base, uint w, uint h, vec2 u, out uvec2 cell, out vec2 f) {
    uint j = dist2d_find(base, h, u.x);
    float m0 = dist_value(base + j), m1 = dist_value(base + j + 1u);
    uint row = base + h + 1u + j * (w + 1u);
    uint i = dist2d_find(row, w, u.y);
    float c0 = dist_value(row + i), c1 = dist_value(row + i + 1u);
    cell = uvec2(i, j);
    f = vec2(clamp((u.y - c0) / (c1 - c0), 0.0, 1.0), clamp((u.x - m0) / (m1 - m0), 0.0, 1.0));
}

// A point of [0, 1]² with density dist2d_cell_density of its cell.
vec2 dist2d_sample(uint base, uint w, uint h, vec2 u) {
    uvec2 cell;
    vec2 f;
    dist2d_sample_cell(base, w, h, u, cell, f);
    return vec2((float(cell.x) + f.x) / float(w), (float(cell.y) + f.y) / float(h));
}

#endif
