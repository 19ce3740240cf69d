// The thin lens's aperture sampling (Mitsuba `thinlens`): a point uniform over the unit
// disk by the concentric map (Shirley and Chiu 1997), scaled by the aperture radius
// by the caller; density 1 / π per unit area. `wavetrace warptest thinlens_aperture`
// tests it.
#ifndef SENSOR_THINLENS_GLSL
#define SENSOR_THINLENS_GLSL

#include "sampling/warp.glsl"

vec2 camera_thinlens_aperture(vec2 u) { return warp_square_to_disk(u); }

// Its density per unit area of the unit disk.
float camera_thinlens_aperture_pdf(vec2 p) { return warp_square_to_disk_pdf(p); }

#endif
