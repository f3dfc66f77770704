// GLSL only: the VPL gathers shared by the gather, negative and refine passes. The includer
// declares `VplRecord vpls[]` and `VplRecord negativeVpls[]` storage buffers before including this.
// No visibility term (as in the paper) unless the includer defines VPL_VISIBILITY (the
// positive VPLs' light is then stopped where their visibility maps say, gi/vpl_visibility.h); the
// loops have run-time trip counts so lavapipe's JIT never unrolls them.
#ifndef VKGI_GI_VPL_GATHER_H
#define VKGI_GI_VPL_GATHER_H
#include "vpl.h"
#include "vpl_term.h"
#ifdef VPL_VISIBILITY
#include "vpl_visibility.h"
#endif

// Irradiance (lux) at x (normal n) from the positive VPLs [first, end): each is a cosine
// emitter, E = flux/pi * vplPositiveTerm (clamp2 times the VPL's footprint). `travel` receives
// the sum of the unit directions the light travels in, weighted by the luminance of each
// contribution.
vec3 vplGatherPositive(vec3 x, vec3 n, uint first, uint end, float clamp2, out vec3 travel) {
    vec3 e = vec3(0.0);
    travel = vec3(0.0);
    for (uint k = first; k < end; ++k) {
        VplRecord v = vpls[k];
        vec3 w;
        float g = vplPositiveTerm(v.position.xyz, v.direction.xyz, x, n, clamp2 * v.flux.w, w);
#ifdef VPL_VISIBILITY
        if (g > 0.0)
            g *= vplVisibility(k, x, n, v.position.xyz, v.direction.xyz);
#endif
        vec3 c = v.flux.rgb * (g * v.position.w);
        e += c;
        travel -= w * vplLuminance(c);
    }
    return e * (1.0 / GI_VPL_PI);
}

// Irradiance the first `count` negative VPLs remove at x: each re-emits the light that crossed
// its surface in a cosine lobe around its travel direction, E = flux/pi * cosLobe * cosX / max(d^2, clamp2 * r^2).
vec3 vplGatherNegative(vec3 x, vec3 n, uint count, float clamp2) {
    vec3 e = vec3(0.0);
    for (uint k = 0u; k < count; ++k) {
        VplRecord v = negativeVpls[k];
        vec3 d = x - v.position.xyz;
        float d2 = dot(d, d);
        vec3 w = d * inversesqrt(max(d2, 1e-30));
        float g = max(dot(v.direction.xyz, w), 0.0) * max(-dot(n, w), 0.0) / max(d2, clamp2 * v.flux.w);
        e += v.flux.rgb * (g * v.position.w);
    }
    return e * (1.0 / GI_VPL_PI);
}

#endif
