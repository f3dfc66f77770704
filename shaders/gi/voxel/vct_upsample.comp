#version 460
#extension GL_GOOGLE_include_directive : require
// Low-res VCT trace -> full resolution: bilinear from the low-res indirect (a = AO) and glossy
// images, next to edges from the taps on the pixel's own surface only; the pixels near edges
// that no tap can stand in for are appended to the refine list (lowResFitTaps in
// gi/lowres_upsample.h). The list header is also the indirect
// dispatch of the refine trace: {count, groups x, 1, 1}, the dispatch read at byte offset 4.
#include "gi/voxel_passes.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push { VctTracePush pc; };
// Point reads only: storage images (lavapipe loads their texels much faster than it fetches
// through a sampler).
layout(set = 1, binding = 0, rgba32f) uniform readonly image2D gPosition;
layout(set = 1, binding = 1, rgba16f) uniform readonly image2D gNormal;
layout(set = 1, binding = 2, rgba32f) uniform readonly image2D lowIndirect;
layout(set = 1, binding = 3, rgba32f) uniform readonly image2D lowGlossy;
layout(set = 1, binding = 4, rgba32f) uniform writeonly image2D outIndirect;
layout(set = 1, binding = 5, rgba32f) uniform writeonly image2D outGlossy;
layout(set = 1, binding = 6, std430) buffer RefineList {
    uint refineCount;
    uint refineGroups[3]; // VkDispatchIndirectCommand of vct_trace_refine.comp (zeroed before)
    uint refinePixels[];  // x | y << 16
};
#define GI_LOWRES_GBUFFER_FETCH(image, pixel) imageLoad(image, pixel)
#include "gi/lowres_upsample.h"

#include "vct_refine.glsl"

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 full = ivec2(pc.cones.info.zw);
    if (any(greaterThanEqual(px, full)))
        return;
    if (px == ivec2(0)) {
        refineGroups[1] = 1u;
        refineGroups[2] = 1u;
    }
    vec4 position = imageLoad(gPosition, px);
    if (position.w == 0.0) {
        imageStore(outIndirect, px, vec4(0.0, 0.0, 0.0, 1.0));
        imageStore(outGlossy, px, vec4(0.0));
        return;
    }
    vec3 n = normalize(imageLoad(gNormal, px).xyz);
    ivec2 taps[4];
    vec4 w;
    // Refined pixels that take another pixel's trace are not listed: that pixel's refine
    // invocation writes them (vctQuadLeader, vct_refine.glsl).
    bool refine = vctRefines(px, position, n, taps, w) && vctQuadLeader(px, position, n) == px;
    vec4 indirect = vec4(0.0), glossy = vec4(0.0);
    for (int k = 0; k < 4; ++k) {
        indirect += w[k] * imageLoad(lowIndirect, taps[k]);
        glossy += w[k] * imageLoad(lowGlossy, taps[k]);
    }
    imageStore(outIndirect, px, indirect);
    imageStore(outGlossy, px, glossy);
    if (refine) {
        uint slot = atomicAdd(refineCount, 1u);
        if (slot < pc.lowRes.w) {
            refinePixels[slot] = uint(px.x) | (uint(px.y) << 16);
            if (slot % GI_VCT_REFINE_GROUP == 0u)
                atomicAdd(refineGroups[0], 1u); // x = ceil(listed / group)
        }
    }
}
