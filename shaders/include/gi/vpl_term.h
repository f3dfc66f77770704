// GLSL only: the VPL-to-receiver term of the gathers (gi/vpl_gather.h) and of the candidates'
// importance (gi/vpl_importance_pass.h), and the luminance the VPL passes weigh light by, written
// once so that the importance estimates exactly what the gather will add.
#ifndef VKGI_GI_VPL_TERM_H
#define VKGI_GI_VPL_TERM_H

float vplLuminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// A positive VPL is a cosine emitter at p facing `dir`: its geometric term at x (normal n) is
// cosX cosVpl / max(d^2, clampArea), where clampArea is the clamp squared times the VPL's
// footprint r^2 (flux.w), so the clamp follows the spacing of the VPLs, not a length of the
// scene. `w` receives the unit direction from x towards the VPL.
float vplPositiveTerm(vec3 p, vec3 dir, vec3 x, vec3 n, float clampArea, out vec3 w) {
    vec3 d = p - x;
    float d2 = dot(d, d);
    w = d * inversesqrt(max(d2, 1e-30));
    return max(dot(n, w), 0.0) * max(-dot(dir, w), 0.0) / max(d2, clampArea);
}

#endif
