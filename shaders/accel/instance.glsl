// Instances (Mitsuba's shapegroup / instance) as the kernels read them; the layout is
// src/accel/instance.rs's. Needs scene_bindings.glsl.
//
// A kernel that traces or shades a scene with instances defines, before including
// anything that includes this file (bvh.glsl, surface.glsl, emitter.glsl):
//   SPEC(SCENE_INSTANCES); SPEC(SCENE_INSTANCE_SLOTS);
//   #define BVH_INSTANCES SCENE_INSTANCES
//   #define BVH_INSTANCE_SLOTS SCENE_INSTANCE_SLOTS
// BVH_INSTANCES is the shift of the hit names, (instance + 1) << shift | primitive, plus
// 32 (accel::instance::COMPACT_BIT) where the instance records are compact; 0 in scenes
// without instances (the default): then every function here is the identity or
// compiles away.
#ifndef INSTANCE_GLSL
#define INSTANCE_GLSL

#ifndef SCENE_BINDINGS_GLSL
#error "include scene_bindings.glsl before instance.glsl"
#endif

#ifndef BVH_INSTANCES
#define BVH_INSTANCES 0u
#endif
#ifndef BVH_INSTANCE_SLOTS
#define BVH_INSTANCE_SLOTS 0u
#endif
#define INSTANCED (BVH_INSTANCES != 0u)
#define INSTANCE_SHIFT (BVH_INSTANCES & 31u)
#define INSTANCE_COMPACT ((BVH_INSTANCES & 32u) != 0u)
// Texels of an instance record: 2 compact, else 4.
#define INSTANCE_TEXELS (4u - 2u * ((BVH_INSTANCES >> 5u) & 1u))

// An instance's map from world to its group's space: p' = A p + b, A by rows. Instance
// record k (instance.rs; k its position in top-level leaf order, as hit names number
// it) starts at texel 3 BVH_INSTANCE_SLOTS + INSTANCE_TEXELS k of the primitives:
// compact, a quaternion (x, y, z, w) whose squared norm is A's scale (w's sign bit: A
// mirrors), then (b, the group's root node); else A's rows with b's components in w,
// then (the group's root node, 0, 0, 0).
struct InstanceMap {
    vec3 r0;
    vec3 r1;
    vec3 r2;
    vec3 b;
};

uint instance_texel(uint k) { return 3u * BVH_INSTANCE_SLOTS + INSTANCE_TEXELS * k; }

// The map of instance k: for a compact record, A rebuilt from its quaternion as
// accel::instance::compact_rows does.
InstanceMap instance_to_object(uint k) {
    uint at = instance_texel(k);
    uvec4 t0 = prim_texel(at);
    uvec4 t1 = prim_texel(at + 1u);
    InstanceMap m;
    if (INSTANCE_COMPACT) {
        vec4 q = uintBitsToFloat(t0);
        float x = q.x, y = q.y, z = q.z, w = abs(q.w);
        float xx = x * x, yy = y * y, zz = z * z, ww = w * w;
        float xy = x * y, xz = x * z, yz = y * z;
        float wx = w * x, wy = w * y, wz = w * z;
        float s = (t0.w & 0x80000000u) != 0u ? -1.0 : 1.0;
        m.r0 = s * vec3(ww + xx - yy - zz, 2.0 * (xy - wz), 2.0 * (xz + wy));
        m.r1 = s * vec3(2.0 * (xy + wz), ww - xx + yy - zz, 2.0 * (yz - wx));
        m.r2 = s * vec3(2.0 * (xz - wy), 2.0 * (yz + wx), ww - xx - yy + zz);
        m.b = uintBitsToFloat(t1.xyz);
    } else {
        uvec4 t2 = prim_texel(at + 2u);
        m.r0 = uintBitsToFloat(t0.xyz);
        m.r1 = uintBitsToFloat(t1.xyz);
        m.r2 = uintBitsToFloat(t2.xyz);
        m.b = uintBitsToFloat(uvec3(t0.w, t1.w, t2.w));
    }
    return m;
}

// The root node of instance k's group.
uint instance_root(uint k) {
    uint at = instance_texel(k);
    return INSTANCE_COMPACT ? prim_texel(at + 1u).w : prim_texel(at + 3u).x;
}

// The linear part of the instance's to_world, A⁻¹.
mat3 instance_to_world_linear(InstanceMap m) {
    return inverse(transpose(mat3(m.r0, m.r1, m.r2)));
}

vec3 instance_point(InstanceMap m, vec3 p) {
    return vec3(dot(m.r0, p), dot(m.r1, p), dot(m.r2, p)) + m.b;
}

vec3 instance_vector(InstanceMap m, vec3 v) {
    return vec3(dot(m.r0, v), dot(m.r1, v), dot(m.r2, v));
}

// The instance a hit name lies in, plus 1 (0: a primitive outside instances).
uint instance_of(uint id) {
    return INSTANCED ? id >> INSTANCE_SHIFT : 0u;
}

// The primitive record a hit name refers to.
uint instance_prim(uint id) {
    return INSTANCED ? id & ((1u << INSTANCE_SHIFT) - 1u) : id;
}

// Primitive `id` (a hit name) in world space: a primitive of an instance mapped by its
// to_world (points by the inverse of A and the stored translation; a quadric's axes as
// vectors), else the record as stored.
Prim instance_prim_load(uint id) {
    Prim p = prim_load(instance_prim(id));
    uint k1 = instance_of(id);
    if (INSTANCED && k1 != 0u) {
        InstanceMap m = instance_to_object(k1 - 1u);
        mat3 to_world = instance_to_world_linear(m);
        vec3 t = -(to_world * m.b); // to_world's translation
        bool triangle = p.kind == PRIM_TRIANGLE;
        p.p0 = to_world * p.p0 + t;
        p.p1 = to_world * p.p1 + (triangle ? t : vec3(0.0));
        p.p2 = to_world * p.p2 + (triangle ? t : vec3(0.0));
    }
    return p;
}

// A normal of the group's space in world space (the inverse transpose of to_world,
// A^T n), not normalized; the identity outside instances.
vec3 instance_normal(uint id, vec3 n) {
    uint k1 = instance_of(id);
    if (INSTANCED && k1 != 0u) {
        InstanceMap m = instance_to_object(k1 - 1u);
        n = n.x * m.r0 + n.y * m.r1 + n.z * m.r2;
    }
    return n;
}

// Whether the hit's instance mirrors (det to_world < 0): a normal computed from the
// mapped vertices then points against Mitsuba's (the inverse transpose of the
// object's), and turns around.
bool instance_mirrors(uint id) {
    uint k1 = instance_of(id);
    bool mirrors = false;
    if (INSTANCED && k1 != 0u) {
        // det A = 1 / det to_world: the same sign.
        InstanceMap m = instance_to_object(k1 - 1u);
        mirrors = dot(m.r0, cross(m.r1, m.r2)) < 0.0;
    }
    return mirrors;
}

// How far the mapping of a point into and out of the instance may move it, per axis,
// added to a hit point's error bound (PBR 4th ed., sec. 6.8.6: transformed points):
// a few ulps of the point and of the translation (recomputed from the record, as
// instance_prim_load does, so within the bound's own few ulps).
vec3 instance_point_error(uint id, vec3 p) {
    uint k1 = instance_of(id);
    vec3 e = vec3(0.0);
    if (INSTANCED && k1 != 0u) {
        InstanceMap m = instance_to_object(k1 - 1u);
        vec3 t = -(instance_to_world_linear(m) * m.b); // to_world's translation
        e = 8.0 * 4.1723283e-7 * (abs(p) + vec3(max(max(abs(t.x), abs(t.y)), abs(t.z))));
    }
    return e;
}

#endif
