// Instances (Mitsuba's shapegroup / instance) as the kernels read them; the layout is
// src/accel/instance.rs's. Needs scene_bindings.glsl.
//
// A kernel that traces or shades a scene with instances defines, before including
// anything that includes this file (bvh.glsl, surface.glsl, emitter.glsl):
//   SPEC(SCENE_INSTANCES); SPEC(SCENE_INSTANCE_SLOTS);
//   #define BVH_INSTANCES SCENE_INSTANCES
//   #define BVH_INSTANCE_SLOTS SCENE_INSTANCE_SLOTS
// BVH_INSTANCES is the shift of the hit names, (instance + 1) << shift | primitive, 0 in
// scenes without instances (the default): then every function here is the identity or
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

// An instance's map from world to its group's space: p' = A p + b, A by rows. Its
// top-level record (instance.rs) holds A's rows in p0, p1, p2, its group's root node
// in `shape` and the instance number k in `index`; b is texel 3 BVH_INSTANCE_SLOTS + k
// of the primitives, whose fourth word is the position of that record.
struct InstanceMap {
    vec3 r0;
    vec3 r1;
    vec3 r2;
    vec3 b;
};

// The map of the instance whose top-level record p was loaded.
InstanceMap instance_map(Prim p) {
    vec3 b = uintBitsToFloat(prim_texel(3u * BVH_INSTANCE_SLOTS + p.index).xyz);
    return InstanceMap(p.p0, p.p1, p.p2, b);
}

// The map of instance k (as hit names number it).
InstanceMap instance_to_object(uint k) {
    uvec4 t = prim_texel(3u * BVH_INSTANCE_SLOTS + k);
    Prim a = prim_load(t.w);
    return InstanceMap(a.p0, a.p1, a.p2, uintBitsToFloat(t.xyz));
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
    return INSTANCED ? id >> BVH_INSTANCES : 0u;
}

// The primitive record a hit name refers to.
uint instance_prim(uint id) {
    return INSTANCED ? id & ((1u << BVH_INSTANCES) - 1u) : id;
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
