#version 460
#extension GL_GOOGLE_include_directive : require
// Low-res VCT trace -> full resolution, one invocation per 2x2 quad of pixels: bilinear from
// the low-res indirect (a = AO) and glossy images, next to edges from the taps on the pixel's
// own surface only; the pixels near edges that no tap can stand in for are refined
// (lowResFitTaps in gi/lowres_upsample.h), and a refined pixel takes the trace of an earlier
// refined pixel of its quad on the same spot (vctSameSpot). Each quad appends its traced pixels
// to the refine list with the quad's pixels each serves (vctRefineEntry). The list header is
// also the indirect dispatch of the refine trace: {count, groups x, 1, 1}, the dispatch read at
// byte offset 4.
//
// Per quad, not per pixel: deciding which refined pixels share a trace needs the other pixels'
// decisions, which a per-pixel invocation recomputed (up to three more tap fits for a refined
// pixel, and again in the refine pass). (Loading a quad's taps once where they are shared, at
// f = 4, measured slower than each pixel loading its own.)
#include "gi/voxel_passes.h"

layout(local_size_x = 8, local_size_y = 8) in; // quads
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
    uint refineEntries[]; // vctRefineEntry
};
#define GI_LOWRES_GBUFFER_FETCH(image, pixel) imageLoad(image, pixel)
#include "gi/lowres_upsample.h"

#include "vct_refine.glsl"

void main() {
    ivec2 quad = ivec2(gl_GlobalInvocationID.xy);
    ivec2 full = ivec2(pc.cones.info.zw);
    ivec2 base = quad * 2;
    bool glossyImage = (pc.cones.info.y & GI_VCT_FLAG_GLOSSY_IMAGE) != 0u;
    if (any(greaterThanEqual(base, full)))
        return;
    if (quad == ivec2(0)) {
        refineGroups[1] = 1u;
        refineGroups[2] = 1u;
    }
    vec4 pos[4];
    vec3 nrm[4];
    bool refined[4] = bool[4](false, false, false, false);
    uint serves[4] = uint[4](0u, 0u, 0u, 0u); // per quad pixel k: the quad pixels its trace writes
    for (int k = 0; k < 4; ++k) {
        ivec2 px = base + ivec2(k & 1, k >> 1);
        pos[k] = vec4(0.0);
        nrm[k] = vec3(0.0, 0.0, 1.0);
        if (any(greaterThanEqual(px, full)))
            continue; // outside the image (odd sizes)
        pos[k] = imageLoad(gPosition, px);
        if (pos[k].w == 0.0) {
            imageStore(outIndirect, px, vec4(0.0, 0.0, 0.0, 1.0));
            if (glossyImage)
                imageStore(outGlossy, px, vec4(0.0));
            continue;
        }
        nrm[k] = normalize(imageLoad(gNormal, px).xyz);
        ivec2 taps[4];
        vec4 w;
        refined[k] = vctRefines(px, pos[k], nrm[k], taps, w);
        // Refined pixels get these too, overwritten by the refine trace.
        vec4 indirect = vec4(0.0);
        for (int j = 0; j < 4; ++j)
            indirect += w[j] * imageLoad(lowIndirect, taps[j]);
        imageStore(outIndirect, px, indirect);
        if (glossyImage) {
            vec4 glossy = vec4(0.0);
            for (int j = 0; j < 4; ++j)
                glossy += w[j] * imageLoad(lowGlossy, taps[j]);
            imageStore(outGlossy, px, glossy);
        }
        if (!refined[k])
            continue;
        // In quad order: the first traced pixel before k on the same spot serves k, else k is traced.
        int leader = k;
        for (int j = k - 1; j >= 0; --j)
            if (serves[j] != 0u && vctSameSpot(pos[k], nrm[k], pos[j], nrm[j]))
                leader = j;
        serves[leader] |= 1u << uint(k);
    }
    uint traced = 0u;
    for (int k = 0; k < 4; ++k)
        traced += serves[k] != 0u ? 1u : 0u;
    if (traced == 0u)
        return;
    uint slot = atomicAdd(refineCount, traced);
    for (int k = 0; k < 4; ++k) {
        if (serves[k] == 0u)
            continue;
        if (slot < pc.lowRes.w) {
            refineEntries[slot] = vctRefineEntry(quad, uint(k), serves[k]);
            if (slot % GI_VCT_REFINE_GROUP == 0u)
                atomicAdd(refineGroups[0], 1u); // x = ceil(listed / group)
        }
        ++slot;
    }
}
