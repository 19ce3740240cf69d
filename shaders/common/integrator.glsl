// Integrator identifiers, mirrored in src/render/integrator.rs (`Integrator::id`).
#ifndef INTEGRATOR_GLSL
#define INTEGRATOR_GLSL

#define INTEGRATOR_NORMALS 0u
#define INTEGRATOR_AO 1u
#define INTEGRATOR_SIMPLE 2u

#endif
