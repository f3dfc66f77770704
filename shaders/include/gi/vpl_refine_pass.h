// GLSL only: the body of the refine pass (vpl_refine.comp; vpl_refine_visible.comp and
// vpl_refine_maps.comp define VPL_VISIBILITY and the way, gi/vpl_visibility.h, first).
// Low-resolution optimisation, second half: the full positive and negative gather for each
// pixel of the refine list, written over the interpolated value.
#ifndef VKGI_GI_VPL_REFINE_PASS_H
#define VKGI_GI_VPL_REFINE_PASS_H
#include "vpl.h"
#include "vpl_refine_list.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_1D) in;
layout(push_constant) uniform PushBlock { VplPixelPush pc; };

layout(set = 1, binding = VPL_REFINE_BINDING_POSITION) uniform sampler2D gPosition;
layout(set = 1, binding = VPL_REFINE_BINDING_NORMAL) uniform sampler2D gNormal;
layout(set = 1, binding = VPL_REFINE_BINDING_ALBEDO) uniform sampler2D gAlbedo;
layout(set = 1, binding = VPL_REFINE_BINDING_VPLS, std430) readonly buffer Vpls { VplRecord vpls[]; };
layout(set = 1, binding = VPL_REFINE_BINDING_NEGATIVE_VPLS, std430) readonly buffer NegativeVpls {
    VplRecord negativeVpls[];
};
VPL_REFINE_LIST_BUFFER(VPL_REFINE_BINDING_REFINE_LIST, readonly);
layout(set = 1, binding = VPL_REFINE_BINDING_INDIRECT, rgba32f) uniform writeonly image2D outIndirect;

#ifdef VPL_VISIBILITY_MARCH
layout(set = 1, binding = VPL_REFINE_BINDING_OCCUPANCY) uniform sampler3D vplOccupancy;
#endif
#ifdef VPL_VISIBILITY_MAPS
layout(set = 1, binding = VPL_REFINE_BINDING_VISIBILITY_MAP, std430) readonly buffer VisibilityMap { float vplVisibilityMap[]; };
#endif

#include "vpl_gather.h"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= min(refineCount, pc.size.w))
        return;
    uint packed = refinePixels[i];
    ivec2 px = ivec2(packed & 0xffffu, packed >> 16);
    vec4 position = texelFetch(gPosition, px, 0);
    vec3 n = texelFetch(gNormal, px, 0).xyz;
    vec3 travel;
    vec3 e = vplGatherPositive(position.xyz, n, 0u, pc.counts.x, pc.params.x, travel);
    vec3 albedo = texelFetch(gAlbedo, px, 0).rgb * (1.0 / GI_VPL_PI);
    vec3 radiance = albedo * e;
    if (pc.counts.y > 0u)
        radiance = max(radiance - albedo * vplGatherNegative(position.xyz, n, pc.counts.y, pc.params.x), vec3(0.0));
    imageStore(outIndirect, px, vec4(radiance, 1.0));
}

#endif
