// Mitsuba 3's stratified samplers, as its plugins define them (src/samplers/*.cpp of
// Mitsuba 3.9): each pixel's sample set (one pass of `count` samples) is a randomly
// permuted stratified pattern; dimension `dim` permutes the sample order with its own
// seed (Mitsuba: seq + dim; here sampler_seed(seq, dim), see sampler_hash.glsl), so
// dimensions are decorrelated and every prefix of the set is still uniformly
// distributed. `seq` is the pixel's sequence seed (sampler.glsl), j the
// sample's index in its pass, `jit` its jitter within the stratum (0.5: no jitter).
// Needs sampler_hash.glsl.
#ifndef SAMPLER_MITSUBA_GLSL
#define SAMPLER_MITSUBA_GLSL

// stratified: a 1-D dimension is stratified into count strata, a 2-D one into a
// res x res grid (count = res^2).
float sampler_stratified_1d(Sampler s, uint seq, uint j, uint dim, float jit) {
    uint p = sampler_permute_kensler(j, s.count, sampler_seed(seq, dim));
    return min((float(p) + jit) / float(s.count), SAMPLER_ONE_MINUS_EPSILON);
}

vec2 sampler_stratified_2d(Sampler s, uint seq, uint j, uint dim, vec2 jit) {
    uint p = sampler_permute_kensler(j, s.count, sampler_seed(seq, dim));
    uint y = p / s.res_x;
    uint x = p - y * s.res_x;
    return min((vec2(x, y) + jit) / float(s.res_x), vec2(SAMPLER_ONE_MINUS_EPSILON));
}

// multijitter: correlated multi-jittered sampling (Kensler 2013, "Correlated
// Multi-Jittered Sampling", Pixar Technical Memo 13-01): a 2-D dimension is stratified
// in the res_x x res_y grid and each of its 1-D projections in count strata (the
// sub-stratum within a cell is the permuted other coordinate); a 1-D one in count strata.
float sampler_multijitter_1d(Sampler s, uint seq, uint j, uint dim, float jit) {
    uint p = sampler_permute_kensler(j, s.count, sampler_seed(seq, dim) ^ 0x45fbe943u);
    return min((float(p) + jit) / float(s.count), SAMPLER_ONE_MINUS_EPSILON);
}

vec2 sampler_multijitter_2d(Sampler s, uint seq, uint j, uint dim, vec2 jit) {
    uint ps = sampler_seed(seq, dim);
    uint c = sampler_permute_kensler(j, s.count, ps ^ 0x51633e2du);
    uint y = c / s.res_x;
    uint x = c - y * s.res_x;
    uint sx = sampler_permute_kensler(x, s.res_x, sampler_mix32(ps ^ 0x68bc21ebu));
    uint sy = sampler_permute_kensler(y, s.res_y, sampler_mix32(ps ^ 0x02e5be93u));
    vec2 u = vec2((float(x) + (float(sy) + jit.x) / float(s.res_y)) / float(s.res_x),
                  (float(y) + (float(sx) + jit.y) / float(s.res_x)) / float(s.res_y));
    return min(u, vec2(SAMPLER_ONE_MINUS_EPSILON));
}

// orthogonal: orthogonal-array sampling (Jarosz, Enayet, Kensler, Kilpatrick and Christensen
// 2019, "Orthogonal Array Sampling for Monte Carlo Rendering"), the multi-jittered
// flavour: sample j of a pixel is row j of a randomly row-permuted orthogonal array of
// `count` = s^2 rows (s = res_x, a prime) and strength t (`strength`), column `col` one
// coordinate. Its value's stratum among s comes from the array's symbol, its sub-stratum
// from another column (strength 2) or the row's remaining digits, each permuted per
// column (seeds sampler_seed(seq, 2 col) and (seq, 2 col + 1) for Mitsuba's
// seq (col + 1) times constants): every pair of columns (strength 2) is stratified on the s x s grid, every
// column in s^2 (or s^t) strata. Mitsuba numbers columns 0, 1, 2, ... by its dimension
// counter; a 1-D dimension d here is column 2d and a 2-D one columns (2d, 2d + 1), the
// pairs Bose's construction couples.
//
// Bose 1938 construction (strength 2): row (a0, a1) = digits of the permuted row index
// in base s; column 0 is a0, column 1 is a1, column c >= 2 is a0 + (c - 1) a1 mod s.
// Columns c and c + s repeat (the array has s + 1 distinct columns), as in Mitsuba.
float sampler_orthogonal_bose(Sampler s, uint seq, uint j, uint col, float jit) {
    uint res = s.res_x;
    uint i = sampler_permute_kensler(j, s.count, seq);
    uint a0 = i / res;
    uint a1 = i - a0 * res;
    uint k = (col & 1u) != 0u ? col - 1u : col + 1u;
    uint a_ij = (a0 + (col - 1u) * a1) % res;
    uint a_ik = (a0 + (k - 1u) * a1) % res;
    if (col == 0u) { a_ij = a0; a_ik = a1; }
    if (col == 1u) { a_ij = a1; a_ik = a0; }
    uint stratum = sampler_permute_kensler(a_ij, res, sampler_seed(seq, 2u * col));
    uint sub = sampler_permute_kensler(a_ik, res, sampler_seed(seq, 2u * col + 1u));
    float u = (float(stratum) + (float(sub) + jit) / float(res)) / float(res);
    return min(u, SAMPLER_ONE_MINUS_EPSILON);
}

// Bush 1952 construction (strength t): the row index, permuted among s^t rows, has
// base-s digits d_0 .. d_{t-1}; column c is the polynomial sum d_l c^l evaluated mod s.
// The sub-stratum comes from the row's digits above the first (s^(t-1) sub-strata).
// Mitsuba 3.9 reads the digits one place off (its first digit is i (1 - s)); this takes
// the base-s digits themselves, so that the array has strength t. As in Mitsuba, a
// pixel uses count = s^2 of the s^t rows, chosen by the row permutation.
float sampler_orthogonal_bush(Sampler s, uint seq, uint j, uint col, uint strength, float jit) {
    uint res = s.res_x;
    uint n = 1u;
    for (uint l = 0u; l < strength; l++) n *= res;
    uint stm = n / res;
    uint i = sampler_permute_kensler(j, n, seq);
    // Horner's rule from the highest digit: phi = sum_l d_l col^l (mod s).
    uint phi = 0u;
    uint c = col % res;
    for (uint l = strength; l-- > 0u;) {
        uint p = 1u;
        for (uint m = 0u; m < l; m++) p *= res;
        uint digit = (i / p) % res;
        phi = (phi * c + digit) % res;
    }
    uint stratum = sampler_permute_kensler(phi, res, sampler_seed(seq, 2u * col));
    uint sub = sampler_permute_kensler((i / res) % stm, stm, sampler_seed(seq, 2u * col + 1u));
    float u = (float(stratum) + (float(sub) + jit) / float(stm)) / float(res);
    return min(u, SAMPLER_ONE_MINUS_EPSILON);
}

// Column col: Bose's construction for SAMPLER_ORTHOGONAL (strength 2), Bush's for
// SAMPLER_ORTHOGONAL_BUSH (the kind is specialized, so only one is compiled).
float sampler_orthogonal(Sampler s, uint kind, uint seq, uint j, uint col, float jit) {
    if (kind == SAMPLER_ORTHOGONAL) return sampler_orthogonal_bose(s, seq, j, col, jit);
    uint strength = (s.flags >> SAMPLER_STRENGTH_SHIFT) & 0xffu;
    return sampler_orthogonal_bush(s, seq, j, col, strength, jit);
}

// ldsampler: Mitsuba's low-discrepancy sampler. Every 2-D dimension of a pixel holds the
// first count = 4^k points of the (0,2)-sequence (van der Corput, Sobol' 2nd dimension),
// randomized by a digital shift (XOR) per pixel, in an order that a TEA shuffling
// network permutes per dimension (padding, Kollig and Keller 2002, "Efficient
// Multidimensional Sampling"); a 1-D dimension is the van der Corput sequence alike.
// The points of a 2-D dimension then form a (0, 2k, 2)-net in base 2.
float sampler_ldsampler_1d(Sampler s, uint seq, uint j, uint dim) {
    uint i = sampler_permute_tea(j, s.count, sampler_seed(seq, dim));
    uint shift = sampler_tea(seq, 0x48bc48ebu, 4u).x;
    return sampler_u32_to_float(bitfieldReverse(i) ^ shift);
}

vec2 sampler_ldsampler_2d(Sampler s, uint seq, uint j, uint dim) {
    uint i = sampler_permute_tea(j, s.count, sampler_seed(seq, dim));
    uvec2 shift = sampler_tea(seq, 0x98bc51abu, 4u);
    return vec2(sampler_u32_to_float(bitfieldReverse(i) ^ shift.x),
                sampler_u32_to_float(sampler_sobol_dim1(i) ^ shift.y));
}

#endif
