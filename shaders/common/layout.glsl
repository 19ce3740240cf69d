// GPU structs shared with the host. Mirrors src/gpu/layout.rs field for field (std430);
// tests in that file check every size and offset.
#ifndef LAYOUT_GLSL
#define LAYOUT_GLSL

// BVH2 node with both children's bounds. count == 0: index is an inner node;
// count > 0: a leaf with primitives [index, index + count). Root is node 0.
struct BvhNode {
    vec3 left_min;
    uint left_index;
    vec3 left_max;
    uint left_count;
    vec3 right_min;
    uint right_index;
    vec3 right_max;
    uint right_count;
};

#define PRIM_TRIANGLE 0u
#define PRIM_SPHERE 1u

// Triangle: vertices p0, p1, p2; index = global triangle number.
// Sphere: center p0, radius p1.x; index = sphere number.
struct Prim {
    vec3 p0;
    uint shape;
    vec3 p1;
    uint index;
    vec3 p2;
    uint kind;
};

#endif
