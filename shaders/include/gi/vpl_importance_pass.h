// GLSL only: the body of the importance pass (vpl_importance.comp; vpl_importance_visible.comp
// defines VPL_VISIBILITY_MARCH first). One thread per candidate VPL of a large sun window
// (docs/vpl.md, "Candidates weighted by the image"): its estimated contribution to the frame,
// the luminance it brings to GI_VPL_IMPORTANCE_PIXELS visible points of the G-buffer (Halton
// pixels, bases 2 and 3), each term the gather's,
//     albedo * flux/pi * cosVpl * cosX / max(d^2, clamp^2 r^2) (* visibility),
// averaged over the points that hold geometry. With the march, roofs and ground outside the
// walls that the camera does not see into weigh nothing; the selection's defensive floor keeps
// them possible (vpl_select.comp).
#ifndef VKGI_GI_VPL_IMPORTANCE_PASS_H
#define VKGI_GI_VPL_IMPORTANCE_PASS_H
#include "vpl.h"
#include "vpl_term.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_1D) in;
layout(push_constant) uniform PushBlock { VplImportancePush pc; };

layout(set = 1, binding = VPL_IMPORTANCE_BINDING_POSITION) uniform sampler2D gPosition;
layout(set = 1, binding = VPL_IMPORTANCE_BINDING_NORMAL) uniform sampler2D gNormal;
layout(set = 1, binding = VPL_IMPORTANCE_BINDING_ALBEDO) uniform sampler2D gAlbedo;
layout(set = 1, binding = VPL_IMPORTANCE_BINDING_CANDIDATES, std430) readonly buffer Candidates { VplRecord candidates[]; };
layout(set = 1, binding = VPL_IMPORTANCE_BINDING_WEIGHTS, std430) writeonly buffer Weights { float weights[]; };
#ifdef VPL_VISIBILITY_MARCH
layout(set = 1, binding = VPL_IMPORTANCE_BINDING_OCCUPANCY) uniform sampler3D vplOccupancy;
#include "vpl_visibility.h"
#endif

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.info.x)
        return;
    VplRecord v = candidates[i];
    float flux = vplLuminance(v.flux.rgb);
    if (!(v.position.w > 0.0) || !(flux > 0.0)) {
        weights[i] = 0.0;
        return;
    }
    vec2 size = vec2(pc.info.zw);
    float clamp2 = pc.params.x * v.flux.w;
    float sum = 0.0;
    uint seen = 0u;
    for (uint k = 1u; k <= pc.info.y; ++k) {
        vec2 halton = vec2(vplRadicalInverse(k, 2u), vplRadicalInverse(k, 3u));
        ivec2 pixel = min(ivec2(halton * size), ivec2(pc.info.zw) - 1);
        vec4 x = texelFetch(gPosition, pixel, 0);
        if (!(x.w > 0.0))
            continue;
        seen += 1u;
        vec3 n = texelFetch(gNormal, pixel, 0).xyz;
        vec3 w;
        float g = vplPositiveTerm(v.position.xyz, v.direction.xyz, x.xyz, n, clamp2, w);
#ifdef VPL_VISIBILITY_MARCH
        if (g > 0.0 && pc.interleave.w > 0u)
            g *= vplVisibility(i, x.xyz, n, v.position.xyz, v.direction.xyz);
#endif
        sum += g * vplLuminance(texelFetch(gAlbedo, pixel, 0).rgb);
    }
    weights[i] = seen > 0u ? flux * sum / (GI_VPL_PI * float(seen)) : 0.0;
}
#endif
