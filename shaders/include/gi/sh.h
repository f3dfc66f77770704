// Spherical harmonics with 2 bands (4 coefficients per colour channel), one definition for
// C++ (namespace vkgi::gpu, GLM types) and GLSL. Used by LPV injection, propagation and lookup.
// Band 2 (below the 2-band functions) serves only the CPU reference's 3-band comparison.
//
// Basis: real, orthonormal over the unit sphere (integral of Yi*Yj over all directions = delta_ij),
// WITHOUT the Condon-Shortley phase, so band 1 is just the direction vector scaled. A vec4 holds
//   .x  Y00 = 1 / (2 sqrt(pi))          = 0.2820948
//   .y  Y1x = sqrt(3 / (4 pi)) * w.x    = 0.4886025 * w.x
//   .z  Y1y = sqrt(3 / (4 pi)) * w.y
//   .w  Y1z = sqrt(3 / (4 pi)) * w.z
// for a unit direction w in world space (right-handed, +Y up). Sloan-style code that stores
// (c0, Y1,-1 = -k y, Y10 = k z, Y11 = -k x) converts to this order as (c0, -c3, -c1, c2).
// A function f(w) is represented by its projection c_i = integral of f * Y_i and reconstructed
// as f(w) ~ dot(c, shBasis(w)); for 2 bands this is exact for every f = a + b.w.
#ifndef VKGI_GI_SH_H
#define VKGI_GI_SH_H

#include "shared/bridge.h"

// Loops that must be unrolled on lavapipe (the quadrature below: unrolled, its directions are
// constants; a rolled loop recomputes them at every call, a large share of the lookup's cost).
#ifdef __cplusplus
#define GI_SH_UNROLL
#else
#extension GL_EXT_control_flow_attributes : require
#define GI_SH_UNROLL [[unroll]]
#endif

GI_NAMESPACE_BEGIN

const float kShPi = 3.14159265f;
const float kShY00 = 0.28209479f;        // 1 / (2 sqrt(pi))
const float kShY1 = 0.48860251f;         // sqrt(3 / (4 pi))
const float kShSphereIntegral = 3.5449077f; // 2 sqrt(pi) = integral of f over the sphere per unit c0
// Projection of the clamped cosine max(0, n.w): band 0 = pi * Y00 = sqrt(pi) / 2,
// band 1 = (2 pi / 3) * Y1 = sqrt(pi / 3) (Ramamoorthi & Hanrahan's A0 = pi, A1 = 2 pi / 3).
const float kShCosineBand0 = 0.88622693f;
const float kShCosineBand1 = 1.02332671f;

// The four basis functions at unit direction `w`.
GI_INLINE vec4 shBasis(vec3 w) {
    return vec4(kShY00, kShY1 * w.x, kShY1 * w.y, kShY1 * w.z);
}

// Reconstructs the represented function in direction `w` (unit).
GI_INLINE float shEvaluate(vec4 sh, vec3 w) {
    return dot(sh, shBasis(w));
}

// Integral of the represented function over all directions (band 1 integrates to zero).
GI_INLINE float shIntegral(vec4 sh) {
    return kShSphereIntegral * sh.x;
}

// Projection of the clamped cosine lobe max(0, n.w) around unit normal `n`. Its integral is pi,
// so a Lambertian emitter of flux F has radiant intensity (F / pi) * shCosineLobe(n).
GI_INLINE vec4 shCosineLobe(vec3 n) {
    return vec4(kShCosineBand0, kShCosineBand1 * n.x, kShCosineBand1 * n.y, kShCosineBand1 * n.z);
}

// Integral of f(w) * max(0, n.w) over all w, where f is the represented function (e.g. incident
// radiance indexed by the direction it comes FROM gives irradiance at a surface with normal n).
// By orthonormality this is the dot product of the two projections; exact for 2-band f.
GI_INLINE float shClampedCosineIntegral(vec4 sh, vec3 n) {
    return dot(sh, shCosineLobe(n));
}

// Integral of f over the hemisphere of directions w with n.w > 0: band 0 times 2 pi Y00,
// band 1 times pi Y1 (the integral of w over a hemisphere is pi n). Exact for 2-band f.
GI_INLINE float shHemisphereIntegral(vec4 sh, vec3 n) {
    return dot(sh, vec4(2.0f * kShPi * kShY00, (kShPi * kShY1) * n));
}

// Integral of max(0, f(w)) * max(0, u.w) over all w, for three functions at once (r, g, b):
// like shClampedCosineIntegral, but only the non-negative part of f counts. A 2-band f is
// a + b.w, negative wherever b.w < -a; for radiance that is truncation ringing (a Lambertian
// lobe (1/pi)(1/4 + cos/2) is negative behind its emitter, and its dot product with a receiver
// facing the emitter's own direction is -1/3 of the lobe's head-on value, which cancels real light
// arriving there). Equal to shClampedCosineIntegral wherever f >= 0 over the hemisphere around
// u. Quadrature: kShPositiveQuadrature directions w_k = rr (cos phi t + sin phi t2) +
// sqrt(1 - rr^2) u, rr = sqrt((k + 1/2) / K), phi = k times the golden angle (a cosine-weighted
// Fibonacci spiral; the angle advances by a fixed rotation, so in the unrolled loop the
// directions fold to constants), weight pi / K each. The kink of max(0, f) limits it to ~2% of
// the head-on value (sh_test.cpp: 1.8% worst over random f at K = 32).
const int kShPositiveQuadrature = 32;
const float kShGoldenCos = -0.73736888f; // cos(pi (3 - sqrt 5))
const float kShGoldenSin = 0.67549029f;
GI_INLINE vec3 shClampedCosineIntegralOfPositivePart(vec4 r, vec4 g, vec4 b, vec3 u) {
    // Orthonormal basis (t, t2, u) without branches on u (Duff et al. 2017).
    float s = u.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + u.z);
    float bb = u.x * u.y * a;
    vec3 t = vec3(1.0f + s * u.x * u.x * a, s * bb, -s * u.x);
    vec3 t2 = vec3(bb, s + u.y * u.y * a, -u.y);
    // Band 1 of each channel in the (t, t2, u) frame; band 0 as the constant term.
    mat3 frame = transpose(mat3(t, t2, u));
    vec3 lr = kShY1 * (frame * vec3(r.y, r.z, r.w)), lg = kShY1 * (frame * vec3(g.y, g.z, g.w)),
         lb = kShY1 * (frame * vec3(b.y, b.z, b.w));
    vec3 c0 = kShY00 * vec3(r.x, g.x, b.x);
    vec3 sum = vec3(0.0f);
    float cp = 1.0f, sp = 0.0f;
    GI_SH_UNROLL for (int k = 0; k < kShPositiveQuadrature; ++k) {
        float q = (float(k) + 0.5f) / float(kShPositiveQuadrature);
        float rr = sqrt(q);
        vec3 w = vec3(rr * cp, rr * sp, sqrt(1.0f - q));
        sum += max(c0 + vec3(dot(lr, w), dot(lg, w), dot(lb, w)), vec3(0.0f));
        float c = cp * kShGoldenCos - sp * kShGoldenSin;
        sp = cp * kShGoldenSin + sp * kShGoldenCos;
        cp = c;
    }
    return sum * (kShPi / float(kShPositiveQuadrature));
}

// Band 2 of 3-band SH, used by the CPU reference's 3-band propagation (gi/src/lpv/lpv_cpu.*), the
// measured and rejected alternative to the GPU's 2 bands (docs/lpv.md, "Alternatives measured and
// rejected"). Bands 0 and 1 stay the vec4 above; band 2 has five coefficients,
// orthonormal like the others and without the Condon-Shortley phase, stored as a vec4 and a float:
//   vec4 (Y2-2 = kShY2xy x y, Y2-1 = kShY2xy y z, Y20 = kShY20 (3 z^2 - 1), Y21 = kShY2xy x z)
//   float  Y22 = kShY22 (x^2 - y^2)
// Each is a linear function of w w^T, so the integral of band 2 over a set of directions follows
// from the set's second moment S = integral of w w^T dw (shBand2FromMoment*); its solid angle is
// trace(S). The clamped cosine's band 2 is (pi / 4) times the basis (Ramamoorthi & Hanrahan's A2).
const float kShY2xy = 1.09254843f; // sqrt(15 / (4 pi))
const float kShY20 = 0.31539157f;  // sqrt(5 / (16 pi))
const float kShY22 = 0.54627422f;  // sqrt(15 / (16 pi))
const float kShCosineBand2 = 0.78539816f; // pi / 4

GI_INLINE vec4 shBasisBand2(vec3 w) {
    return vec4(kShY2xy * w.x * w.y, kShY2xy * w.y * w.z, kShY20 * (3.0f * w.z * w.z - 1.0f), kShY2xy * w.x * w.z);
}
GI_INLINE float shBasisBand2Last(vec3 w) {
    return kShY22 * (w.x * w.x - w.y * w.y);
}

// Band 2 of integral Y dw over a set of directions with second moment S (symmetric; columns).
GI_INLINE vec4 shBand2FromMoment(mat3 s) {
    float omega = s[0][0] + s[1][1] + s[2][2];
    return vec4(kShY2xy * s[0][1], kShY2xy * s[1][2], kShY20 * (3.0f * s[2][2] - omega), kShY2xy * s[0][2]);
}
GI_INLINE float shBand2FromMomentLast(mat3 s) {
    return kShY22 * (s[0][0] - s[1][1]);
}

// Band 2 of the clamped cosine lobe max(0, n.w) (with shCosineLobe: its 3-band projection).
GI_INLINE vec4 shCosineLobeBand2(vec3 n) {
    return kShCosineBand2 * shBasisBand2(n);
}
GI_INLINE float shCosineLobeBand2Last(vec3 n) {
    return kShCosineBand2 * shBasisBand2Last(n);
}

// shClampedCosineIntegralOfPositivePart of one 3-band function (bands 0-1 `sh`, band 2 `q`,
// `q4`): the same quadrature directions, band 2 evaluated at each direction in world space.
GI_INLINE float shClampedCosineIntegralOfPositivePart3(vec4 sh, vec4 q, float q4, vec3 u) {
    float s = u.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + u.z);
    float bb = u.x * u.y * a;
    vec3 t = vec3(1.0f + s * u.x * u.x * a, s * bb, -s * u.x);
    vec3 t2 = vec3(bb, s + u.y * u.y * a, -u.y);
    float sum = 0.0f;
    float cp = 1.0f, sp = 0.0f;
    GI_SH_UNROLL for (int k = 0; k < kShPositiveQuadrature; ++k) {
        float qq = (float(k) + 0.5f) / float(kShPositiveQuadrature);
        float rr = sqrt(qq);
        vec3 w = (rr * cp) * t + (rr * sp) * t2 + sqrt(1.0f - qq) * u;
        sum += max(shEvaluate(sh, w) + dot(q, shBasisBand2(w)) + q4 * shBasisBand2Last(w), 0.0f);
        float c = cp * kShGoldenCos - sp * kShGoldenSin;
        sp = cp * kShGoldenSin + sp * kShGoldenCos;
        cp = c;
    }
    return sum * (kShPi / float(kShPositiveQuadrature));
}

// One function: shClampedCosineIntegralOfPositivePart(sh, sh, sh, u).x.
GI_INLINE float shClampedCosineIntegralOfPositivePart(vec4 sh, vec3 u) {
    return shClampedCosineIntegralOfPositivePart(sh, sh, sh, u).x;
}

GI_NAMESPACE_END

#endif
