// Ray/sdfgrid intersection and hit geometry (src/scene/shape/sdfgrid.rs): the zero set
// of the trilinear interpolant of a grid of distances, as Mitsuba 3.9's sdfgrid finds
// it. Needs scene_bindings.glsl (grid_word, grid_value).
//
// Layout in the grid buffer at the primitive's offset (p2.x bits; sdfgrid::pack):
// 24 header words (world or group space to voxel coordinates as three rows of a 3x4
// matrix; the samples per axis; the flags; the box of the occupied voxels), the samples ((z ny + y) nx + x), then one
// occupancy bit per voxel. Voxel coordinates put sample (x, y, z) at (x, y, z): voxel v
// spans [v, v + 1].
//
// The test walks the voxels along the ray front to back (Amanatides, Woo 1987, "A Fast
// Voxel Traversal Algorithm"); in each occupied one the interpolant along the ray is a
// cubic in t (Hansson-Söderlund, Evans, Akenine-Möller 2022, "Ray Tracing of Signed
// Distance Function Grids", JCGT 11(3)), whose first root is bracketed between the
// roots of its derivative and refined by Newton steps that fall back to bisection
// (Marmitt, Kleer, Wald, Friedrich 2004, "Fast and Accurate Ray-Voxel Intersection
// Techniques for Iso-Surface Ray Tracing"), to 1e-5 in t as Mitsuba.
#ifndef INTERSECT_SDFGRID_GLSL
#define INTERSECT_SDFGRID_GLSL

#define SDF_HEADER_WORDS 24u
#define SDF_SMOOTH 1u
// Mitsuba's NumSolveEpsilon (ray parameter units) and iteration cap.
#define SDF_SOLVE_EPSILON 1e-5
#define SDF_SOLVE_MAX_ITER 50u

struct SdfHeader {
    vec4 r0; // world (group) space -> voxel coordinates, by rows
    vec4 r1;
    vec4 r2;
    uvec3 res; // samples per axis
    uint flags;
    uint data; // offset of the samples
    vec3 lo;   // the box of the occupied voxels, in voxel coordinates
    vec3 hi;
};

SdfHeader sdf_header(uint offset) {
    SdfHeader h;
    vec4 m[3];
    for (uint r = 0u; r < 3u; r++) {
        m[r] = vec4(grid_value(offset + 4u * r), grid_value(offset + 4u * r + 1u),
                    grid_value(offset + 4u * r + 2u), grid_value(offset + 4u * r + 3u));
    }
    h.r0 = m[0];
    h.r1 = m[1];
    h.r2 = m[2];
    h.res = uvec3(grid_word(offset + 12u).x, grid_word(offset + 13u).x, grid_word(offset + 14u).x);
    h.flags = grid_word(offset + 15u).x;
    h.lo = vec3(grid_value(offset + 16u), grid_value(offset + 17u), grid_value(offset + 18u));
    h.hi = vec3(grid_value(offset + 20u), grid_value(offset + 21u), grid_value(offset + 22u));
    h.data = offset + SDF_HEADER_WORDS;
    return h;
}

vec3 sdf_point(SdfHeader h, vec3 p) {
    vec4 q = vec4(p, 1.0);
    return vec3(dot(h.r0, q), dot(h.r1, q), dot(h.r2, q));
}

vec3 sdf_vector(SdfHeader h, vec3 v) {
    return vec3(dot(h.r0.xyz, v), dot(h.r1.xyz, v), dot(h.r2.xyz, v));
}

// A voxel-space gradient as a world (group) space normal, not normalized: the inverse
// transpose of voxel-to-world, M^T g.
vec3 sdf_normal(SdfHeader h, vec3 g) {
    return g.x * h.r0.xyz + g.y * h.r1.xyz + g.z * h.r2.xyz;
}

float sdf_sample(SdfHeader h, ivec3 q) {
    ivec3 c = clamp(q, ivec3(0), ivec3(h.res) - 1);
    return grid_value(h.data + (uint(c.z) * h.res.y + uint(c.y)) * h.res.x + uint(c.x));
}

// The eight samples of voxel v, corner i at (i & 1, (i >> 1) & 1, i >> 2).
void sdf_corners(SdfHeader h, ivec3 v, out float s[8]) {
    uint base = h.data + (uint(v.z) * h.res.y + uint(v.y)) * h.res.x + uint(v.x);
    for (uint i = 0u; i < 8u; i++) {
        s[i] = grid_value(base + ((i >> 2) * h.res.y + ((i >> 1) & 1u)) * h.res.x + (i & 1u));
    }
}

bool sdf_occupied(SdfHeader h, ivec3 v) {
    uvec3 n = h.res - 1u;
    uint i = (uint(v.z) * n.y + uint(v.y)) * n.x + uint(v.x);
    uint w = grid_word(h.data + h.res.x * h.res.y * h.res.z + (i >> 5u)).x;
    return (w & (1u << (i & 31u))) != 0u;
}

// The trilinear interpolant of corners s at w in [0, 1]^3 (mix is exact at 0 and 1, so
// two voxels agree on their shared face).
float sdf_trilerp(float s[8], vec3 w) {
    float a = mix(mix(s[0], s[1], w.x), mix(s[2], s[3], w.x), w.y);
    float b = mix(mix(s[4], s[5], w.x), mix(s[6], s[7], w.x), w.y);
    return mix(a, b, w.z);
}

// Its gradient: each partial derivative the bilinear interpolant of the differences
// along the four parallel edges.
vec3 sdf_trilerp_grad(float s[8], vec3 w) {
    float gx = mix(mix(s[1] - s[0], s[3] - s[2], w.y), mix(s[5] - s[4], s[7] - s[6], w.y), w.z);
    float gy = mix(mix(s[2] - s[0], s[3] - s[1], w.x), mix(s[6] - s[4], s[7] - s[5], w.x), w.z);
    float gz = mix(mix(s[4] - s[0], s[5] - s[1], w.x), mix(s[6] - s[2], s[7] - s[3], w.x), w.y);
    return vec3(gx, gy, gz);
}

float sdf_cubic(vec4 c, float t) {
    return ((c.w * t + c.z) * t + c.y) * t + c.x;
}

// The first root in [0, t_end] of the cubic c (c.x + c.y t + c.z t^2 + c.w t^3), whose
// values at the ends are f_beg and f_end (computed from the samples, so that
// neighbouring voxels agree on their shared face). False if the interval brackets none.
bool sdf_solve(vec4 c, float t_end, float f_beg, float f_end, out float t) {
    // Split [0, t_end] at the roots of the derivative 3 c3 t^2 + 2 c2 t + c1 (in
    // increasing order), keeping the first part over which the sign changes.
    float a = 3.0 * c.w, b = 2.0 * c.z;
    float r0 = 0.0, r1 = 0.0;
    bool roots;
    if (a == 0.0) {
        roots = b != 0.0;
        r0 = -c.y / b;
        r1 = r0;
    } else {
        float disc = b * b - 4.0 * a * c.y;
        roots = disc >= 0.0;
        float q = -0.5 * (b + (b >= 0.0 ? sqrt(max(disc, 0.0)) : -sqrt(max(disc, 0.0))));
        float x0 = q / a, x1 = c.y / q;
        r0 = min(x0, x1);
        r1 = max(x0, x1);
    }
    float t_near = 0.0, t_far = t_end, f_near = f_beg, f_far = f_end;
    for (uint k = 0u; k < 2u; k++) {
        float r = k == 0u ? r0 : r1;
        if (roots && t_near <= r && r <= t_far) {
            float fr = sdf_cubic(c, r);
            if (f_near * fr <= 0.0) {
                t_far = r;
                f_far = fr;
            } else {
                t_near = r;
                f_near = fr;
            }
        }
    }
    bool found = f_near * f_far <= 0.0;
    // The secant's estimate (the midpoint where it falls outside), then Newton steps
    // kept inside the shrinking bracket by bisection.
    t = t_near + (t_far - t_near) * (-f_near / (f_far - f_near));
    if (!(t >= t_near && t <= t_far)) t = 0.5 * (t_near + t_far);
    bool done = !found;
    for (uint i = 0u; i <= SDF_SOLVE_MAX_ITER && !done; i++) {
        float ft = sdf_cubic(c, t);
        if (ft * f_near <= 0.0) {
            t_far = t;
        } else {
            t_near = t;
        }
        float deriv = (a * t + b) * t + c.y;
        float next = t - ft / deriv;
        if (ft == 0.0) {
            next = t;
        } else if (!(next > t_near && next < t_far)) {
            next = 0.5 * (t_near + t_far);
        }
        done = !(abs(next - t) >= SDF_SOLVE_EPSILON);
        t = next;
    }
    return found;
}

// The hit of ray o + t d (voxel coordinates of voxel v: o is relative to its lower
// corner) with voxel v's surface for t in [ta, tb]; `enter` and `leave`: the axis whose
// face the ray crosses at ta and tb (-1: none), whose coordinate is snapped to the face.
bool sdf_voxel_hit(SdfHeader h, ivec3 v, vec3 o, vec3 d, float ta, float tb, int enter,
                   int leave, out float t) {
    float s[8];
    sdf_corners(h, v, s);
    vec3 pa = o + ta * d;
    vec3 pb = o + tb * d;
    for (int k = 0; k < 3; k++) {
        if (k == enter) pa[k] = d[k] >= 0.0 ? 0.0 : 1.0;
        if (k == leave) pb[k] = d[k] >= 0.0 ? 1.0 : 0.0;
    }
    pa = clamp(pa, 0.0, 1.0);
    pb = clamp(pb, 0.0, 1.0);
    float f_beg = sdf_trilerp(s, pa);
    float f_end = sdf_trilerp(s, pb);
    // f = A + z B along the ray from pa, with A = k0 + k1 x + k2 y + k3 x y and B the
    // same over the upper face's differences; x y = m0 + m1 t + m2 t^2.
    float k0 = s[0], k1 = s[1] - s[0], k2 = s[2] - s[0], k3 = s[3] - s[2] - s[1] + s[0];
    float k4 = s[4] - s[0], k5 = (s[5] - s[4]) - k1, k6 = (s[6] - s[4]) - k2;
    float k7 = (s[7] - s[6] - s[5] + s[4]) - k3;
    float m0 = pa.x * pa.y, m1 = pa.x * d.y + pa.y * d.x, m2 = d.x * d.y;
    vec3 ac = vec3(k0 + k1 * pa.x + k2 * pa.y + k3 * m0, k1 * d.x + k2 * d.y + k3 * m1, k3 * m2);
    vec3 bc = vec3(k4 + k5 * pa.x + k6 * pa.y + k7 * m0, k5 * d.x + k6 * d.y + k7 * m1, k7 * m2);
    vec4 c = vec4(ac.x + pa.z * bc.x, ac.y + pa.z * bc.y + d.z * bc.x,
                  ac.z + pa.z * bc.z + d.z * bc.y, d.z * bc.z);
    float u;
    bool found = sdf_solve(c, tb - ta, f_beg, f_end, u);
    t = ta + u;
    return found && t >= ta && t <= tb;
}

// One step of the voxel walk of intersect_sdfgrid: into the next voxel through the face
// the ray leaves by first, or done where that leaves the grid or the ray's range.
#define SDF_ADVANCE                                                                      \
    {                                                                                    \
        int a_ = next.x <= next.y && next.x <= next.z ? 0 : (next.y <= next.z ? 1 : 2);  \
        bool out_ = next[a_] > te;                                                       \
        v[a_] += step[a_];                                                               \
        budget--;                                                                        \
        if (out_ || v[a_] < vlo[a_] || v[a_] >= vhi[a_] || budget <= 0) {              \
            done = true;                                                                 \
        } else {                                                                         \
            ta = next[a_];                                                               \
            enter = a_;                                                                  \
            next[a_] += delta[a_];                                                       \
        }                                                                                \
    }

// Closest hit of ray (o, d) (world or group space) with the sdfgrid of primitive p in
// (tmin, tmax): t, and in `voxel` the linear index of the voxel hit (as a float: exact
// below 2^24 voxels), which the hit geometry reads back.
bool intersect_sdfgrid(vec3 o, vec3 d, Prim p, float tmin, float tmax, out float t,
                       out float voxel) {
    SdfHeader h = sdf_header(floatBitsToUint(p.p2.x));
    vec3 ov = sdf_point(h, o);
    vec3 dv = sdf_vector(h, d);
    ivec3 n = ivec3(h.res) - 1;
    ivec3 vlo = ivec3(h.lo), vhi = ivec3(h.hi);
    // The box of the occupied voxels in t.
    vec3 inv = vec3(1.0) / dv;
    vec3 t0 = (mix(h.lo, h.hi, lessThan(dv, vec3(0.0))) - ov) * inv;
    vec3 t1 = (mix(h.hi, h.lo, lessThan(dv, vec3(0.0))) - ov) * inv;
    float tb = tmin, te = tmax;
    int enter = -1;
    for (int k = 0; k < 3; k++) {
        // A zero direction component: inside its slab or not at all (NaN: on a plane).
        float a = isnan(t0[k]) ? -1e30 : t0[k];
        float b = isnan(t1[k]) ? 1e30 : t1[k];
        if (a > tb) {
            tb = a;
            enter = k;
        }
        te = min(te, b);
    }
    bool found = false;
    t = tmax;
    voxel = 0.0;
    if (tb <= te) {
        vec3 pb = ov + tb * dv;
        ivec3 v = clamp(ivec3(floor(pb)), vlo, vhi - 1);
        ivec3 step = ivec3(sign(dv));
        // Where the ray leaves the current voxel along each axis.
        vec3 next;
        for (int k = 0; k < 3; k++) {
            float face = float(v[k] + (dv[k] > 0.0 ? 1 : 0));
            next[k] = dv[k] == 0.0 ? 1e30 : (face - ov[k]) * inv[k];
        }
        vec3 delta = abs(inv);
        float ta = tb;
        // Voxels are left in t order, so the walk ends; the count only guards rounding.
        int budget = (vhi.x - vlo.x) + (vhi.y - vlo.y) + (vhi.z - vlo.z) + 3;
        bool done = false;
        // "While-while" (as bvh.glsl's traversal): SIMD lanes step through empty voxels
        // together, one occupancy load a step, and solve in occupied voxels together,
        // instead of every step paying for the solve of whichever lane needs one.
        while (!done) {
            bool occupied = sdf_occupied(h, v);
            if (!occupied) do {
                SDF_ADVANCE
                occupied = !done && sdf_occupied(h, v);
            } while (!done && !occupied);
            if (done) break;
            int axis = next.x <= next.y && next.x <= next.z ? 0 : (next.y <= next.z ? 1 : 2);
            float tx = min(next[axis], te);
            int leave = next[axis] <= te ? axis : -1;
            float th;
            if (sdf_voxel_hit(h, v, ov - vec3(v), dv, ta, tx, enter, leave, th)
                && th > tmin && th < tmax) {
                found = true;
                done = true;
                t = th;
                voxel = float((v.z * n.y + v.y) * n.x + v.x);
            } else {
                SDF_ADVANCE
            }
        }
    }
    return found;
}

// Mitsuba's smooth shading normal (Hansson-Söderlund et al. 2022, sec. 5) at voxel
// point pv, as a gradient in voxel units (for sdf_normal): the gradients of the eight
// voxels around the grid vertex nearest pv, each normalized, blended trilinearly.
// A voxel's gradient is made of finite differences of the interpolant across it along
// one axis, at pv's position along the other two; voxels outside the grid get weight 0.
vec3 sdf_smooth(SdfHeader h, vec3 pv) {
    ivec3 res = ivec3(h.res);
    ivec3 v = ivec3(roundEven(pv)) - 1;
    vec3 uvw = pv - vec3(v) - 0.5;
    ivec3 cell = clamp(ivec3(floor(pv)), ivec3(0), res - 2);
    vec3 w = pv - vec3(cell);
    vec3 d0, d1;
    for (int a = 0; a < 3; a++) {
        int b = (a + 1) % 3, c = (a + 2) % 3;
        bool upper = cell[a] != v[a];
        // The interpolant on the sample planes cell[a], cell[a] + 1 and the one beyond
        // on the side of the other voxel.
        float g[3];
        for (int j = 0; j < 3; j++) {
            int q = cell[a] + (j == 0 ? 0 : (j == 1 ? 1 : (upper ? -1 : 2)));
            float f[4];
            for (int i = 0; i < 4; i++) {
                ivec3 idx;
                idx[a] = q;
                idx[b] = cell[b] + (i & 1);
                idx[c] = cell[c] + (i >> 1);
                f[i] = sdf_sample(h, idx);
            }
            g[j] = mix(mix(f[0], f[1], w[b]), mix(f[2], f[3], w[b]), w[c]);
        }
        float dc = g[1] - g[0];
        float dq = upper ? g[0] - g[2] : g[2] - g[1];
        // Per unit of object space ([0, 1]^3), where Mitsuba normalizes them.
        float scale = float(res[a] - 1);
        d0[a] = (upper ? dq : dc) * scale;
        d1[a] = (upper ? dc : dq) * scale;
    }
    bvec3 inside = greaterThanEqual(v, ivec3(0));
    uvw = mix(vec3(1.0), uvw, inside);
    vec3 nb[8];
    for (int i = 0; i < 8; i++) {
        bvec3 hi = bvec3((i & 1) != 0, (i & 2) != 0, (i & 4) != 0);
        vec3 g = mix(d0, d1, hi);
        bool keep = all(bvec3(hi.x || inside.x, hi.y || inside.y, hi.z || inside.z));
        float len = length(g);
        nb[i] = keep && len > 0.0 ? g / len : vec3(0.0);
    }
    vec3 blend = mix(mix(mix(nb[0], nb[1], uvw.x), mix(nb[2], nb[3], uvw.x), uvw.y),
                     mix(mix(nb[4], nb[5], uvw.x), mix(nb[6], nb[7], uvw.x), uvw.y), uvw.z);
    // Back to voxel units, for sdf_normal.
    return blend / vec3(res - 1);
}

// Hit geometry of sdfgrid primitive p (as stored: its offset in p2.x) at the group or
// world space point `pg` in voxel `voxel` (intersect_sdfgrid's): the geometric normal
// (the interpolant's gradient) and the shading normal (smooth or the same), both in
// group space, unit.
void sdf_surface(Prim p, vec3 pg, float voxel, out vec3 ng, out vec3 ns) {
    SdfHeader h = sdf_header(floatBitsToUint(p.p2.x));
    ivec3 n = ivec3(h.res) - 1;
    int i = int(voxel);
    ivec3 v = ivec3(i % n.x, (i / n.x) % n.y, i / (n.x * n.y));
    vec3 pv = sdf_point(h, pg);
    float s[8];
    sdf_corners(h, v, s);
    vec3 g = sdf_trilerp_grad(s, clamp(pv - vec3(v), 0.0, 1.0));
    ng = normalize(sdf_normal(h, g));
    ns = ng;
    if ((h.flags & SDF_SMOOTH) != 0u) {
        vec3 sm = sdf_normal(h, sdf_smooth(h, pv));
        float len = length(sm);
        if (len > 0.0) ns = sm / len;
    }
}

#endif
