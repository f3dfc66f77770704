// GLSL only: the body of the gather pass (vpl_gather.comp; vpl_gather_visible.comp and
// vpl_gather_maps.comp define VPL_VISIBILITY and the way, gi/vpl_visibility.h, first).
// Deferred VPL shading over the G-buffer (paper section 3.2), at the gather resolution: pixel
// (i, j) of a 1/f-resolution image shades the G-buffer sample at (i f + f/2, j f + f/2).
// Writes the indirect radiance albedo/pi * E, and for the negative VPLs the VPL irradiance E
// and the luminance-weighted sum of the directions that light travels in.
// Interleaved (tile side n > 1): pixel (x, y) gathers only subset (y mod n) n + (x mod n), scaled
// by (all VPLs / the subset's), and gi/vpl_interleave_filter.h averages the subsets back. Work
// groups are laid out so that all invocations of a group share one subset (the group's pixels
// are every n-th pixel of the image, as in a de-interleaved sub-image), so the VPL loop reads the
// same records in every lane.
#ifndef VKGI_GI_VPL_GATHER_PASS_H
#define VKGI_GI_VPL_GATHER_PASS_H
#include "vpl.h"
#include "vpl_surface.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_2D, local_size_y = GI_VPL_LOCAL_SIZE_2D) in;
layout(push_constant) uniform PushBlock { VplPixelPush pc; };

layout(set = 1, binding = VPL_GATHER_BINDING_POSITION) uniform sampler2D gPosition;
layout(set = 1, binding = VPL_GATHER_BINDING_NORMAL) uniform sampler2D gNormal;
layout(set = 1, binding = VPL_GATHER_BINDING_ALBEDO) uniform sampler2D gAlbedo;
layout(set = 1, binding = VPL_GATHER_BINDING_VPLS, std430) readonly buffer Vpls { VplRecord vpls[]; };
layout(set = 1, binding = VPL_GATHER_BINDING_INDIRECT, rgba32f) uniform writeonly image2D outIndirect;
layout(set = 1, binding = VPL_GATHER_BINDING_INCIDENT, rgba32f) uniform writeonly image2D outIncident;
layout(set = 1, binding = VPL_GATHER_BINDING_TRAVEL, rgba32f) uniform writeonly image2D outTravel;

layout(set = 1, binding = VPL_GATHER_BINDING_SURFACE, rgba32ui) uniform writeonly uimage2D outSurface;
#ifdef VPL_VISIBILITY_MARCH
layout(set = 1, binding = VPL_GATHER_BINDING_OCCUPANCY) uniform sampler3D vplOccupancy;
#endif
#ifdef VPL_VISIBILITY_MAPS
layout(set = 1, binding = VPL_GATHER_BINDING_VISIBILITY_MAP, std430) readonly buffer VisibilityMap { float vplVisibilityMap[]; };
#endif

// No negative VPLs are read here; the shared gather header still needs the name.
#define negativeVpls vpls
#include "vpl_gather.h"

void main() {
    uint side = pc.interleave.x;
    uvec2 subSize = (pc.size.xy + side - 1u) / side;                      // pixels of one subset
    uvec2 groups = (subSize + GI_VPL_LOCAL_SIZE_2D - 1u) / GI_VPL_LOCAL_SIZE_2D; // groups per subset
    uvec2 cell = gl_WorkGroupID.xy / groups;                         // position in the tile
    uvec2 inSubset = (gl_WorkGroupID.xy % groups) * GI_VPL_LOCAL_SIZE_2D + gl_LocalInvocationID.xy;
    ivec2 px = ivec2(inSubset * side + cell);
    if (any(greaterThanEqual(uvec2(px), pc.size.xy)))
        return;
    uint s = cell.y * side + cell.x;
    uint first = vplSubsetStart(s, side, pc.interleave.y, pc.interleave.z);
    uint end = vplSubsetStart(s + 1u, side, pc.interleave.y, pc.interleave.z);
    int f = int(pc.size.z);
    ivec2 sample_ = min(px * f + f / 2, ivec2(pc.counts.zw) - 1);
    vec4 position = texelFetch(gPosition, sample_, 0);
    vec3 e = vec3(0.0);
    vec3 travel = vec3(0.0);
    vec3 radiance = vec3(0.0);
    vec3 n = vec3(0.0);
    if (position.w > 0.0) {
        n = texelFetch(gNormal, sample_, 0).xyz;
        e = vplGatherPositive(position.xyz, n, first, end, pc.params.x, travel);
        if (side > 1u) {
            // The subset's share of the VPLs is about 1/n^2 but not exactly (N / n^2 blocks are
            // whole): scaled by its own share, every subset estimates the full sum, so a window
            // cut to some subsets stays unbiased (on an integrating sphere, exact).
            float scale = end > first ? float(pc.counts.x) / float(end - first) : 0.0;
            e *= scale;
            travel *= scale;
        } else {
            radiance = texelFetch(gAlbedo, sample_, 0).rgb * e * (1.0 / GI_VPL_PI);
        }
    }
    // Interleaved, the filter passes make the radiance from the irradiance and the surfaces,
    // and only the negative VPLs read the travel directions: the writes nobody reads are left out.
    if (side == 1u)
        imageStore(outIndirect, px, vec4(radiance, 1.0));
    else
        imageStore(outSurface, px, vplSurfacePack(position, n));
    imageStore(outIncident, px, vec4(e, 0.0));
    if (side == 1u || pc.params.w > 0.0)
        imageStore(outTravel, px, vec4(travel, 0.0));
}

#endif
