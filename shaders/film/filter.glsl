// Reconstruction filters, separable: a sample at d = (pixel centre - sample position)
// weighs f(d.x) f(d.y). Which filter is the constant FILM_FILTER (a FILTER_* value,
// a specialization constant defined before including this file), so the others
// compile away; its parameters are film.filter_params (FilmParams in layout.glsl).
// Mirrored by scene::film::Filter::eval (src/scene/film.rs), which the tests compare
// with Mitsuba 3's and Nori's filters. Needs film/film.glsl.
#ifndef FILM_FILTER_GLSL
#define FILM_FILTER_GLSL

#define FILM_PI 3.14159265358979

float filter_eval(float x) {
    vec4 p = film.filter_params;
    float ax = abs(x);
    if (FILM_FILTER == FILTER_TENT) {
        // max(0, 1 - |x| / r); p.x = 1 / r.
        return max(0.0, 1.0 - ax * p.x);
    } else if (FILM_FILTER == FILTER_GAUSSIAN) {
        // A Gaussian less its value at the radius r, so that it ends at 0 there
        // (Mitsuba's gaussian, Nori's GaussianFilter); p.x = -1 / 2σ², p.y = exp(p.x r²).
        return max(0.0, exp(p.x * x * x) - p.y);
    } else if (FILM_FILTER == FILTER_MITCHELL) {
        // Mitchell and Netravali 1988, eq. 8, of t = 2|x| / radius (p.z = 2 / radius);
        // B = p.x, C = p.y. Catmull-Rom is B = 0, C = 1/2.
        float b = p.x;
        float c = p.y;
        float t = ax * p.z;
        float t2 = t * t;
        float t3 = t2 * t;
        float near = (12.0 - 9.0 * b - 6.0 * c) * t3 + (-18.0 + 12.0 * b + 6.0 * c) * t2 + (6.0 - 2.0 * b);
        float far = (-b - 6.0 * c) * t3 + (6.0 * b + 30.0 * c) * t2 + (-12.0 * b - 48.0 * c) * t + (8.0 * b + 24.0 * c);
        return t < 1.0 ? near / 6.0 : (t < 2.0 ? far / 6.0 : 0.0);
    } else if (FILM_FILTER == FILTER_LANCZOS) {
        // sinc(x) sinc(x / lobes) inside |x| < lobes (p.x = lobes).
        float x1 = FILM_PI * ax;
        float x2 = x1 / p.x;
        float v = ax < 1.1920929e-7 ? 1.0 : sin(x1) * sin(x2) / (x1 * x2);
        return ax < p.x ? v : 0.0;
    }
    // The box: every sample weighs 1 in its own pixel (film_gather reaches no other).
    return 1.0;
}

// The weight of a sample at offset `d` (pixel centre minus sample position) from a
// pixel.
float filter_weight(vec2 d) {
    if (FILM_FILTER == FILTER_BOX) return 1.0;
    return filter_eval(d.x) * filter_eval(d.y);
}

#endif
