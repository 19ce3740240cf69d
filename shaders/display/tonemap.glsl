// How the viewer shows linear values: exactly what image::png writes, so a
// screenshot of the window equals the render's PNG (src/image/png.rs): scale by
// 2^exposure, NaN to 0, clamp to [0, 1], the sRGB transfer function
// (IEC 61966-2-1), then round to 8 bits.
#ifndef DISPLAY_TONEMAP_GLSL
#define DISPLAY_TONEMAP_GLSL

// Mitsuba's sRGB luminance weights (hdrfilm's "Y"; render::film::LUMINANCE).
const vec3 TONEMAP_LUMINANCE = vec3(0.212671, 0.715160, 0.072169);

// The sRGB opto-electronic transfer function, linear [0, 1] to encoded [0, 1].
float tonemap_srgb_oetf(float v) {
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

// One linear value, scaled by `scale`, to its 8-bit sRGB code.
uint tonemap_encode(float v, float scale) {
    v *= scale;
    // NaN to 0 explicitly: clamp keeps it.
    v = isnan(v) ? 0.0 : clamp(v, 0.0, 1.0);
    return uint(tonemap_srgb_oetf(v) * 255.0 + 0.5);
}

// A film pixel's sums (Σ w r, Σ w g, Σ w b, Σ w) developed as FilmSums::develop does
// (0 where no sample weighs it), shown as RGB or as luminance, packed as 8-bit RGBA
// (R in the lowest byte, opaque).
uint tonemap_pixel(vec4 sums, float scale, bool luminance) {
    float w = sums.w != 0.0 ? sums.w : 1.0;
    vec3 c = sums.rgb / w;
    if (luminance) {
        c = vec3(dot(TONEMAP_LUMINANCE, c));
    }
    uvec3 b = uvec3(tonemap_encode(c.r, scale), tonemap_encode(c.g, scale),
                    tonemap_encode(c.b, scale));
    return b.r | (b.g << 8) | (b.b << 16) | (255u << 24);
}

#endif
