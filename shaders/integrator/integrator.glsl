// Integrator identifiers, mirrored in src/render/integrator.rs (`Integrator::id`).
#ifndef INTEGRATOR_GLSL
#define INTEGRATOR_GLSL

#define INTEGRATOR_NORMALS 0u
#define INTEGRATOR_AO 1u
#define INTEGRATOR_SIMPLE 2u
#define INTEGRATOR_DIRECT_EMS 3u
#define INTEGRATOR_DIRECT_MATS 4u
#define INTEGRATOR_DIRECT_MIS 5u
#define INTEGRATOR_PATH_MATS 6u
#define INTEGRATOR_PATH_MIS 7u
#define INTEGRATOR_VOL_PATH_SIMPLE 8u
#define INTEGRATOR_VOL_PATH_MIS 9u
#define INTEGRATOR_SINGLE_DISTANCE 10u
#define INTEGRATOR_SINGLE_EQUIANGULAR 11u
// The photon mappers run kernels of their own (shaders/kernels/photon_*, sppm_*).
#define INTEGRATOR_PHOTONMAPPER 12u
#define INTEGRATOR_SPPM 13u
#define INTEGRATOR_PTRACER 14u
// Mitsuba's `depth`: a first-hit integrator (first_hit.glsl), numbered after the others.
#define INTEGRATOR_DEPTH 15u

// Whether `shade` runs the integrator's first hit only (first_hit.glsl).
bool integrator_is_first_hit(uint integrator) {
    return integrator < INTEGRATOR_DIRECT_EMS || integrator == INTEGRATOR_DEPTH;
}

bool integrator_is_single_scatter(uint integrator) {
    return integrator == INTEGRATOR_SINGLE_DISTANCE || integrator == INTEGRATOR_SINGLE_EQUIANGULAR;
}

bool integrator_is_volumetric(uint integrator) {
    return integrator == INTEGRATOR_VOL_PATH_SIMPLE || integrator == INTEGRATOR_VOL_PATH_MIS
        || integrator_is_single_scatter(integrator);
}

// Whether the integrator weighs emitter sampling against BSDF sampling by MIS
// (path.glsl, path_emitted.glsl).
bool integrator_uses_mis(uint integrator) {
    return integrator == INTEGRATOR_DIRECT_MIS || integrator == INTEGRATOR_PATH_MIS
        || integrator == INTEGRATOR_VOL_PATH_MIS || integrator_is_single_scatter(integrator);
}

// Whether the integrator samples emitters at surface vertices (path.glsl; in media,
// the medium decides).
bool integrator_samples_emitters(uint integrator) {
    return integrator == INTEGRATOR_DIRECT_EMS || integrator == INTEGRATOR_DIRECT_MIS
        || integrator == INTEGRATOR_PATH_MIS || integrator == INTEGRATOR_VOL_PATH_MIS
        || integrator_is_single_scatter(integrator);
}

#endif
