// Participating media: where a ray first scatters (free-flight sampling) and how much
// of it gets through a segment (transmittance), for homogeneous and grid media. Needs
// scene_bindings.glsl. All distances are world-space ray parameters t along a unit
// direction; extinction is per unit length and per RGB channel.
#ifndef MEDIUM_GLSL
#define MEDIUM_GLSL

#include "sampling/rng.glsl"
#include "numeric/convert.glsl"

#define MEDIUM_INF uintBitsToFloat(0x7f800000u)

// The medium features of the scene (MEDIUM_FEATURE_* bits); a kernel may define it as
// a specialization constant so that the code of absent features compiles away (on
// llvmpipe a runtime branch costs both sides whatever its lanes take).
#ifndef MEDIUM_FEATURES
#define MEDIUM_FEATURES 0xffffffffu
#endif
#define MEDIUM_HAS(f) ((MEDIUM_FEATURES & (f)) != 0u)
// Whether the scene has grid media (without them the tracking loops compile away).
#define MEDIA_GRIDS MEDIUM_HAS(MEDIUM_FEATURE_GRIDS)
// Whether medium record m is homogeneous (in a scene with grids).
#define MEDIUM_IS_HOMOGENEOUS(m) \
    (!MEDIA_GRIDS || (MEDIUM_HAS(MEDIUM_FEATURE_HOMOGENEOUS) && (m).kind == MEDIUM_HOMOGENEOUS))
// Tentative collisions one tracking loop may take before it gives up (the path or
// shadow ray then carries nothing): a guard against pathological grids, far above
// what the majorant grid needs (optical depth of the majorants along the ray).
#define MEDIUM_MAX_STEPS 65536u
// Ratio tracking plays Russian roulette once the transmittance drops below this.
#define MEDIUM_RR_THRESHOLD 0.1

// Every function here (and in vol_path.glsl, transmittance.glsl) returns once, at its
// end: the kernels of scenes with media are inlined before lavapipe sees them
// (gpu::specialize::INLINE_PASSES), and spirv-opt's merge-return turns a function
// with early returns into a loop around its body, whose bookkeeping llvmpipe pays
// for inside the tracking and crossing loops (shade +12%, shadow +15% on the media
// cube before these functions were written so).

// Random numbers for the unbounded loops of tracking: one stream per path, bounce and
// purpose (0: free flight, 1: shadow transmittance), indexed by a counter. Their
// dimensions have the top bit set, so they never meet those of rng_dim_bounce; below
// it, the purpose (2 bits), the bounce modulo 2048 (11 bits; with 7 bits, bounces 128
// apart drew the same numbers) and the counter (18 bits: 262144 draws per bounce, four
// times MEDIUM_MAX_STEPS). Bounces past 2048 (paths may take up to
// integrator.rs MAX_BOUNCES) also change the seed word, so no two bounces of a path
// share a stream. The first draw's xy may come from a sampler dimension instead
// (medium_rng_first), so that a stratified sampler stratifies it.
struct MediumRng {
    uint pixel;
    uint sample_index;
    uint base;
    uint seed;
    uint n;
    bool has_first;
    vec2 first;
};

MediumRng medium_rng(uint pixel, uint sample_index, uint depth, uint stream, uint seed) {
    uint base = 0x80000000u | ((stream & 3u) << 29) | ((depth & 0x7ffu) << 18);
    return MediumRng(pixel, sample_index, base, seed ^ ((depth >> 11) * 0x9e3779b9u), 0u, false, vec2(0.0));
}

// Makes u the xy of the stream's first draw.
void medium_rng_first(inout MediumRng r, vec2 u) {
    r.has_first = true;
    r.first = u;
}

vec4 medium_rng_next(inout MediumRng r) {
    vec4 u = rng_4d(r.pixel, r.sample_index, r.base | (r.n & 0x3ffffu), r.seed);
    if (r.has_first && r.n == 0u) u.xy = r.first;
    r.n += 1u;
    return u;
}

// The medium a ray leaving shape `shape` (geometric normal ng there) along d travels
// in: as Mitsuba's target_medium, the exterior towards the normal, the interior
// against it; a shape that bounds no media keeps the current one.
uint medium_after(uint shape, uint current, vec3 d, vec3 ng) {
    ShapeRecord s = shape_load(shape);
    uint m = dot(d, ng) > 0.0 ? (s.media >> 16) : (s.media & 0xffffu);
    uint after = m == MEDIUM_NONE16 ? NONE : m;
    return (s.flags & SHAPE_MEDIUM_TRANSITION) == 0u ? current : after;
}

// Beer-Lambert transmittance e^{-σ t} per channel, with e^{-0·∞} = 1.
vec3 medium_tr(vec3 sigma, float t) {
    return vec3(sigma.x > 0.0 ? exp(-sigma.x * t) : 1.0,
                sigma.y > 0.0 ? exp(-sigma.y * t) : 1.0,
                sigma.z > 0.0 ? exp(-sigma.z * t) : 1.0);
}

float medium_avg(vec3 v) { return (v.x + v.y + v.z) * (1.0 / 3.0); }

// The cell of a trilinear lookup at grid-local point pl (the unit cube) in a grid of
// `res` voxels: interpolation between voxel centres, clamped at the edges (as
// Mitsuba 3's gridvolume). f: floor of the voxel coordinate; w: weights of the upper
// voxels; i0, i1: the lower and upper voxels, clamped.
struct GridCell {
    ivec3 res;
    vec3 f;
    vec3 w;
    ivec3 i0;
    ivec3 i1;
};

GridCell medium_grid_cell(uvec3 res, vec3 pl) {
    GridCell c;
    c.res = ivec3(res);
    vec3 x = pl * vec3(res) - 0.5;
    c.f = floor(x);
    c.w = clamp(x - c.f, 0.0, 1.0);
    c.i0 = clamp(ivec3(c.f), ivec3(0), c.res - 1);
    c.i1 = clamp(ivec3(c.f) + 1, ivec3(0), c.res - 1);
    return c;
}

// Corner k of cell c (bit a of k: the upper voxel along axis a): its voxel index, and
// its interpolation weight in `weight`.
uint medium_grid_corner(GridCell c, uint k, out float weight) {
    bvec3 hi = bvec3((k & 1u) != 0u, (k & 2u) != 0u, (k & 4u) != 0u);
    ivec3 i = ivec3(hi.x ? c.i1.x : c.i0.x, hi.y ? c.i1.y : c.i0.y, hi.z ? c.i1.z : c.i0.z);
    vec3 wk = mix(1.0 - c.w, c.w, vec3(hi));
    weight = wk.x * wk.y * wk.z;
    return uint((i.z * c.res.y + i.y) * c.res.x + i.x);
}

// A grid of `res` voxels with `channels` channels at `data` in the grid buffer, at
// grid-local point pl: trilinear interpolation (medium_grid_cell).
vec3 medium_grid_lookup(uvec3 res, uint data, uint channels, vec3 pl) {
    GridCell c = medium_grid_cell(res, pl);
    vec3 d = vec3(0.0);
    for (uint k = 0u; k < 8u; k++) {
        float weight;
        uint idx = medium_grid_corner(c, k, weight);
        if (MEDIUM_HAS(MEDIUM_FEATURE_WORDS1) && channels == 1u) {
            d += vec3(weight * grid_value(data + idx));
        }
        if (MEDIUM_HAS(MEDIUM_FEATURE_WORDS3) && channels != 1u) {
            uint b = data + 3u * idx;
            d += weight * vec3(grid_value(b), grid_value(b + 1u), grid_value(b + 2u));
        }
    }
    return d;
}

// The density of grid medium m at grid-local point pl, as medium_grid_lookup, read
// from its packed texels where the record has them (MEDIUM_DENSITY_PACKED;
// src/render/media.rs pack_density): 2 fetches for one channel, 8 for three.
vec3 medium_grid_density(MediumRecord m, vec3 pl) {
    vec3 d = vec3(0.0);
    if (MEDIUM_HAS(MEDIUM_FEATURE_DENSITY_WORDS) && (m.flags & MEDIUM_DENSITY_PACKED) == 0u) {
        d = medium_grid_lookup(m.res, m.data, m.channels, pl);
    } else {
        GridCell c = medium_grid_cell(m.res, pl);
        if (MEDIUM_HAS(MEDIUM_FEATURE_PACKED1) && m.channels == 1u) {
            // Texel (x, y, z) holds the values at (x, y), (x+1, y), (x, y+1), (x+1, y+1)
            // of slice z. Before the first voxel centre of an axis both corners are
            // voxel 0, but its texel pairs it with voxel 1: weight that one 0 there.
            vec3 w = mix(c.w, vec3(0.0), lessThan(c.f, vec3(0.0)));
            vec4 a = grid_packed(m.data + uint((c.i0.z * c.res.y + c.i0.y) * c.res.x + c.i0.x));
            vec4 b = grid_packed(m.data + uint((c.i1.z * c.res.y + c.i0.y) * c.res.x + c.i0.x));
            vec2 ra = mix(a.xz, a.yw, w.x); // along x, rows y and y+1 of slice z
            vec2 rb = mix(b.xz, b.yw, w.x); // of slice z+1
            d = vec3(mix(mix(ra.x, ra.y, w.y), mix(rb.x, rb.y, w.y), w.z));
        } else {
            for (uint k = 0u; MEDIUM_HAS(MEDIUM_FEATURE_PACKED3) && k < 8u; k++) {
                float weight;
                uint idx = medium_grid_corner(c, k, weight);
                d += weight * grid_packed(m.data + idx).xyz;
            }
        }
    }
    return d;
}

// Extinction at grid-local point pl: the record's per-channel scale times the density.
vec3 medium_grid_sigma_t(MediumRecord m, vec3 pl) {
    return m.sigma_t * medium_grid_density(m, pl);
}

// Single-scattering albedo of medium m (of either kind) at world point p: the
// record's constant, or its albedo grid (MEDIUM_FEATURE_ALBEDO_GRID) looked up in its
// own grid, as Mitsuba looks each volume up with its own to_world and resolution. At
// m.albedo_data in the grid buffer: a header (record.rs albedo_grid_header: the
// world-to-grid map's first three rows, the resolution's bits, the channel count),
// then the values.
vec3 medium_albedo(MediumRecord m, vec3 p) {
    vec3 albedo = m.albedo;
    if (MEDIUM_HAS(MEDIUM_FEATURE_ALBEDO_GRID) && m.albedo_data != NONE) {
        uint h = m.albedo_data;
        vec4 p4 = vec4(p, 1.0);
        vec3 pl;
        for (uint r = 0u; r < 3u; r++) {
            uint k = h + 4u * r;
            pl[r] = dot(vec4(grid_value(k), grid_value(k + 1u), grid_value(k + 2u), grid_value(k + 3u)), p4);
        }
        uvec3 res = uvec3(floatBitsToUint(grid_value(h + 12u)), floatBitsToUint(grid_value(h + 13u)),
                          floatBitsToUint(grid_value(h + 14u)));
        uint channels = (m.flags & MEDIUM_ALBEDO_RGB) != 0u ? 3u : 1u;
        albedo = medium_grid_lookup(res, h + 16u, channels, pl);
    }
    return albedo;
}

// A walk through the cells of a grid medium's majorant grid along a ray (Amanatides
// and Woo 1987, "A Fast Voxel Traversal Algorithm for Ray Tracing"), in grid-local
// coordinates where the ray parameter t is the world one (the map is affine).
struct MajorantWalk {
    vec3 ol;
    vec3 dl;
    ivec3 cell;
    ivec3 step;
    vec3 t_next;  // t at which the walk crosses into the next cell, per axis
    vec3 t_delta; // t across one cell, per axis
    float t;      // start of the current segment
    float t_end;  // where the ray leaves the grid (or tmax)
};

// Starts the walk of ray (o, d) on [0, tmax); false if it misses the grid.
bool medium_walk_begin(MediumRecord m, vec3 o, vec3 d, float tmax, out MajorantWalk w) {
    w.ol = (m.world_to_grid * vec4(o, 1.0)).xyz;
    w.dl = (m.world_to_grid * vec4(d, 0.0)).xyz;
    float t0 = 0.0, t1 = tmax;
    bool inside = true;
    for (int a = 0; a < 3; a++) {
        if (abs(w.dl[a]) < 1e-30) {
            if (w.ol[a] < 0.0 || w.ol[a] > 1.0) inside = false;
        } else {
            float inv = 1.0 / w.dl[a];
            float ta = -w.ol[a] * inv, tb = (1.0 - w.ol[a]) * inv;
            t0 = max(t0, min(ta, tb));
            t1 = min(t1, max(ta, tb));
        }
    }
    inside = inside && t0 < t1;
    w.t = t0;
    w.t_end = t1;
    vec3 M = vec3(m.maj_res);
    ivec3 last = ivec3(m.maj_res) - 1;
    w.cell = clamp(ivec3(floor((w.ol + t0 * w.dl) * M)), ivec3(0), last);
    for (int a = 0; a < 3; a++) {
        if (abs(w.dl[a]) < 1e-30) {
            w.step[a] = 0;
            w.t_next[a] = MEDIUM_INF;
            w.t_delta[a] = MEDIUM_INF;
        } else if (w.dl[a] > 0.0) {
            w.step[a] = 1;
            w.t_next[a] = (float(w.cell[a] + 1) / M[a] - w.ol[a]) / w.dl[a];
            w.t_delta[a] = 1.0 / (M[a] * w.dl[a]);
        } else {
            w.step[a] = -1;
            w.t_next[a] = (float(w.cell[a]) / M[a] - w.ol[a]) / w.dl[a];
            w.t_delta[a] = -1.0 / (M[a] * w.dl[a]);
        }
    }
    return inside;
}

// The majorant of the walk's current cell and the end of its segment.
float medium_walk_cell(MediumRecord m, MajorantWalk w, out float t_cell_end) {
    t_cell_end = min(min(w.t_next.x, w.t_next.y), min(w.t_next.z, w.t_end));
    uvec3 c = uvec3(w.cell);
    return majorant_value(m.maj_data + (c.z * m.maj_res.y + c.y) * m.maj_res.x + c.x);
}

// Moves the walk to the next cell; false when the ray has left the grid or tmax.
bool medium_walk_next(MediumRecord m, inout MajorantWalk w, float t_cell_end) {
    bool going = t_cell_end < w.t_end;
    if (going) {
        w.t = t_cell_end;
        int a = w.t_next.x <= w.t_next.y ? (w.t_next.x <= w.t_next.z ? 0 : 2)
                                         : (w.t_next.y <= w.t_next.z ? 1 : 2);
        w.cell[a] += w.step[a];
        going = w.cell[a] >= 0 && w.cell[a] < int(m.maj_res[a]);
        if (going) w.t_next[a] += w.t_delta[a];
    }
    return going;
}

// Outcomes of medium_walk_collide.
#define MEDIUM_COLLISION 0u // a tentative collision at w.t
#define MEDIUM_LEFT 1u      // the walk left the grid or reached its end
#define MEDIUM_STUCK 2u     // MEDIUM_MAX_STEPS tentative collisions taken

// The walk's next tentative collision (delta and ratio tracking share it): within the
// current cell at rate mu, its majorant, moving on cell by cell where the distance
// drawn passes the cell's end. u: the numbers drawn for it (u.x took the distance).
// `steps` counts the collisions of the whole walk.
uint medium_walk_collide(MediumRecord m, inout MajorantWalk w, inout uint steps,
                         inout MediumRng rng, out float mu, out vec4 u) {
    uint outcome = MEDIUM_LEFT;
    u = vec4(0.0);
    while (true) {
        float t_cell_end;
        mu = medium_walk_cell(m, w, t_cell_end);
        bool collided = false;
        if (mu > 0.0) {
            if (++steps >= MEDIUM_MAX_STEPS) {
                outcome = MEDIUM_STUCK;
                break;
            }
            u = medium_rng_next(rng);
            w.t -= log(1.0 - u.x) / mu;
            collided = w.t < t_cell_end;
        }
        if (collided) {
            outcome = MEDIUM_COLLISION;
            break;
        }
        if (!medium_walk_next(m, w, t_cell_end)) break;
    }
    return outcome;
}

// What happens to a ray in a medium before it reaches tmax (a surface, or ∞).
struct MediumEvent {
    bool scattered; // a real scattering event at t (else the ray reaches tmax)
    float t;
    vec3 weight;    // factor for the path throughput: 0 when absorbed
};

// Samples where ray (o, d) in medium `mi` first scatters before tmax, returning a
// weight whose expectation over the event gives the radiative transfer estimate:
//
// - Homogeneous: distances in closed form from the exponential of one channel picked
//   uniformly, weighted by the one-sample balance heuristic over the three channels
//   (PBR 3rd ed., sec. 15.2.1): at t < tmax, weight σs e^{-σt t} / avg(σt e^{-σt t});
//   reaching tmax, e^{-σt tmax} / avg(e^{-σt tmax}). Grey media: weight = albedo at a
//   scattering event, 1 otherwise. A pure absorber (albedo 0) cannot scatter: its
//   weight is the transmittance itself, with no variance.
// - Grid: delta tracking (Woodcock et al. 1965) with the majorant of each cell of the
//   majorant grid: tentative collisions at rate μ; a real one with probability
//   avg(σt)/μ, weight σs / avg(σt); a null one otherwise, weight σn / avg(σn), σn =
//   μ - σt (grey σt: weights albedo and 1, the classic algorithm; coloured σt:
//   spectral tracking after Kutz et al. 2017, "Spectral and Decomposition Tracking").
MediumEvent medium_sample(uint mi, vec3 o, vec3 d, float tmax, inout MediumRng rng) {
    MediumEvent ev;
    ev.scattered = false;
    ev.t = tmax;
    ev.weight = vec3(1.0);
    MediumRecord m = medium_load(mi);
    MajorantWalk w;
    if (MEDIUM_IS_HOMOGENEOUS(m)) {
        vec3 st = m.sigma_t;
        if (all(equal(m.albedo, vec3(0.0)))) {
            ev.weight = medium_tr(st, tmax);
        } else {
            vec4 u = medium_rng_next(rng);
            uint c = min(floor_to_uint(u.x * 3.0), 2u);
            float sc = st[c];
            float t = sc > 0.0 ? -log(1.0 - u.y) / sc : MEDIUM_INF;
            if (t < tmax) {
                vec3 tr = medium_tr(st, t);
                float pdf = medium_avg(st * tr);
                ev.scattered = true;
                ev.t = t;
                ev.weight = pdf > 0.0 ? st * medium_albedo(m, o + t * d) * tr / pdf : vec3(0.0);
            } else {
                vec3 tr = medium_tr(st, tmax);
                float p = medium_avg(tr);
                ev.weight = p > 0.0 ? tr / p : vec3(0.0);
            }
        }
    } else if (medium_walk_begin(m, o, d, tmax, w)) {
        uint steps = 0u;
        while (true) {
            float mu;
            vec4 u;
            uint outcome = medium_walk_collide(m, w, steps, rng, mu, u);
            if (outcome == MEDIUM_STUCK) ev.weight = vec3(0.0);
            if (outcome != MEDIUM_COLLISION) break;
            vec3 pl = w.ol + w.t * w.dl;
            vec3 st = medium_grid_sigma_t(m, pl);
            float avg_t = medium_avg(st);
            if (u.y * mu < avg_t) {
                ev.scattered = true;
                ev.t = w.t;
                ev.weight *= st * medium_albedo(m, o + w.t * d) / avg_t;
                break;
            }
            vec3 sn = max(vec3(mu) - st, vec3(0.0));
            float avg_n = medium_avg(sn);
            if (avg_n > 0.0) ev.weight *= sn / avg_n;
        }
    }
    return ev;
}

// Transmittance of medium `mi` along (o, d) over [0, tmax): closed form in a
// homogeneous medium, ratio tracking in a grid (Novák et al. 2014, "Residual Ratio
// Tracking for Estimating Attenuation in Participating Media": a factor σn/μ per
// tentative collision), with Russian roulette once it falls below
// MEDIUM_RR_THRESHOLD (survival probability = its largest channel).
vec3 medium_transmittance(uint mi, vec3 o, vec3 d, float tmax, inout MediumRng rng) {
    MediumRecord m = medium_load(mi);
    vec3 T = vec3(1.0);
    MajorantWalk w;
    if (MEDIUM_IS_HOMOGENEOUS(m)) {
        T = medium_tr(m.sigma_t, tmax);
    } else if (medium_walk_begin(m, o, d, tmax, w)) {
        uint steps = 0u;
        while (true) {
            float mu;
            vec4 u;
            uint outcome = medium_walk_collide(m, w, steps, rng, mu, u);
            if (outcome == MEDIUM_STUCK) T = vec3(0.0);
            if (outcome != MEDIUM_COLLISION) break;
            vec3 st = medium_grid_sigma_t(m, w.ol + w.t * w.dl);
            T *= max(vec3(mu) - st, vec3(0.0)) / mu;
            float q = max(T.x, max(T.y, T.z));
            if (q < MEDIUM_RR_THRESHOLD) {
                if (u.y >= q) {
                    T = vec3(0.0);
                    break;
                }
                T /= q;
            }
        }
    }
    return T;
}

#endif
