#version 460
#extension GL_GOOGLE_include_directive : require
// Low-res VCT trace -> full resolution, one invocation per 4x4 block of pixels (vctRefineBlock):
// bilinear from the low-res incoming diffuse (a = AO) and glossy light, each pixel's own albedo
// and metallic applied after (a checkered floor keeps its tiles), next to edges from the taps on
// the pixel's own surface only; the pixels near edges that no tap can stand in for are refined
// (lowResFitTapsAt in gi/lowres_upsample.h), and a refined pixel takes the trace of an earlier
// refined pixel of its block on the same spot (vctSameSpot). Each block appends its traced
// pixels to the refine list with the block's pixels each serves (vctRefineEntry). The list
// header is also the indirect dispatch of the refine trace: {count, groups x, 1, 1}, the
// dispatch read at byte offset 4.
//
// Per block, not per pixel: deciding which refined pixels share a trace needs the other pixels'
// decisions, and at f = 4 the blocks are aligned so that all 16 pixels interpolate the same 2x2
// low-res texels, whose G-buffer samples and values are loaded once per block (12 loads instead
// of 12 per pixel).
#include "gi/vct_passes.h"

layout(local_size_x = 8, local_size_y = 8) in; // blocks
layout(push_constant) uniform Push { VctTracePush pc; };
// Point reads only: storage images (lavapipe loads their texels much faster than it fetches
// through a sampler).
layout(set = 1, binding = VCT_UPSAMPLE_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(set = 1, binding = VCT_UPSAMPLE_BINDING_NORMAL, rgba16f) uniform readonly image2D gNormal;
layout(set = 1, binding = VCT_UPSAMPLE_BINDING_LOW_INDIRECT, rgba32f) uniform readonly image2D lowIndirect;
layout(set = 1, binding = VCT_UPSAMPLE_BINDING_LOW_GLOSSY, rgba32f) uniform readonly image2D lowGlossy;
layout(set = 1, binding = VCT_UPSAMPLE_BINDING_INDIRECT, rgba32f) uniform writeonly image2D outIndirect;
layout(set = 1, binding = VCT_UPSAMPLE_BINDING_GLOSSY, rgba32f) uniform writeonly image2D outGlossy;
layout(set = 1, binding = VCT_UPSAMPLE_BINDING_ALBEDO, rgba16f) uniform readonly image2D gAlbedo; // w = metallic
layout(set = 1, binding = VCT_UPSAMPLE_BINDING_REFINE_LIST, std430) buffer RefineList {
    uint refineCount;
    uint refineGroups[3]; // VkDispatchIndirectCommand of vct_trace_refine.comp ({0, 1, 1} before: vct_trace.comp)
    uvec2 refineEntries[]; // vctRefineEntry
};
#define GI_LOWRES_GBUFFER_FETCH(image, pixel) imageLoad(image, pixel)
#include "gi/lowres_upsample.h"

#include "vct_refine.glsl"

// Traced pixels a block keeps as candidates for serving its later refined pixels (Cornell 256^2:
// 1845 traced pixels against 1818 with all 16 kept, 1943 with 4).
const int kSlots = 6;

// The indirect radiance (a = AO) of pixel px from the incoming diffuse light `d` (a = AO) and
// glossy light `g` the low-res trace stored: the pixel's own albedo and metallic applied. With
// the filter (GI_VCT_FLAG_INCOMING) the incoming diffuse light itself: vct_filter.comp applies them.
vec4 radianceAt(ivec2 px, vec4 d, vec4 g) {
    if ((pc.cones.info.y & GI_VCT_FLAG_INCOMING) != 0u)
        return d;
    vec4 albedo = imageLoad(gAlbedo, px);
    return vec4(albedo.rgb * mix(d.rgb, g.rgb, clamp(albedo.w, 0.0, 1.0)), d.a);
}

// Writes entry `slot` of the refine list (up to its capacity) and counts the refine trace's groups.
void listEntry(uint slot, uvec2 entry) {
    if (slot >= pc.lowRes.w)
        return;
    refineEntries[slot] = entry;
    if (slot % GI_VCT_REFINE_GROUP == 0u)
        atomicAdd(refineGroups[0], 1u); // x = ceil(listed / group)
}

// The G-buffer samples (q, nq, qa) and low-res indirect and glossy values (li, lg) of pixel px's taps.
void loadTaps(ivec2 px, int f, ivec2 low, ivec2 full, out vec4 q[4], out vec3 nq[4], out vec4 qa[4], out vec4 li[4],
              out vec4 lg[4]) {
    ivec2 taps[4];
    vec4 unused;
    lowResTapCell(px, f, low, taps, unused);
    for (int j = 0; j < 4; ++j) {
        ivec2 src = lowResSource(taps[j], f, full);
        q[j] = imageLoad(gPosition, src);
        nq[j] = imageLoad(gNormal, src).xyz;
        qa[j] = imageLoad(gAlbedo, src);
        li[j] = imageLoad(lowIndirect, taps[j]);
        lg[j] = imageLoad(lowGlossy, taps[j]);
    }
}

// Index k (x = k & 3, y = k >> 2) in the block of pixel s of cell c: the block holds (4 / f)^2
// cells of f x f pixels (f = 2 or 4), a single cell at f = 4, whose pixels go centre first
// (vctRefineOrder); at f = 2 the cells go in raster order and their pixels too.
uint blockPixel(int f, int c, int s) {
    if (f == 4)
        return vctRefineOrder(s);
    int side = 4 / f;
    ivec2 xy = ivec2(c % side, c / side) * f + ivec2(s % f, s / f);
    return uint(xy.x + 4 * xy.y);
}

void main() {
    ivec2 full = ivec2(pc.cones.info.zw);
    int f = int(pc.lowRes.x);
    ivec2 low = ivec2(pc.lowRes.yz);
    // llvmpipe runs 8 invocations of a group row as one SIMD batch: each batch takes a 4x2 tile
    // of the group's 8x8 blocks (16x8 pixels) instead of a row (32x4), which crosses fewer
    // edges (fewer batches run the edge code).
    uint lane = gl_LocalInvocationIndex;
    ivec2 block = ivec2(gl_WorkGroupID.xy) * 8 +
                  ivec2((lane & 3u) | ((lane >> 1u) & 4u), ((lane >> 2u) & 1u) | ((lane >> 3u) & 6u));
    ivec2 base = vctRefineBlockOrigin(block, f);
    // The filter's column pass reads the glossy light too.
    bool glossyImage = (pc.cones.info.y & (GI_VCT_FLAG_GLOSSY_IMAGE | GI_VCT_FLAG_INCOMING)) != 0u;
    if (any(greaterThanEqual(base, full)))
        return;
    // The block's first kSlots traced pixels: position, normal, index in the block, pixels
    // served (indexed in loops of constant length, so they stay in registers; a traced pixel
    // beyond them, rare, serves only itself).
    vec4 leadPos[kSlots];
    vec3 leadNrm[kSlots];
    uint leadK[kSlots];
    uint leadServes[kSlots];
    int leaders = 0;
    uint alone = 0u; // traced pixels beyond the slots
    // Per cell (its pixels share their taps: loaded once), two loops: the first gives the pixels
    // off edges (most) their bilinear interpolation and marks the others, the second runs the
    // edge code (the rest of the tap fit, the sharing) for the marked ones only. llvmpipe (Mesa
    // 22) runs both sides of every branch, masked, but leaves a loop once no lane is in it: the
    // edge code then runs as often as the batch's lane with the most edge pixels needs it, not
    // at every pixel.
    int cells = (4 / f) * (4 / f);
    for (int c = 0; c < cells; ++c) {
        vec4 q[4];
        vec3 nq[4];
        vec4 qa[4];
        vec4 li[4], lg[4];
        loadTaps(base + ivec2(blockPixel(f, c, 0) & 3u, blockPixel(f, c, 0) >> 2), f, low, full, q, nq, qa, li, lg);
        uint edges = 0u, background = 0u;
        for (int s = 0; s < f * f; ++s) {
            uint k = blockPixel(f, c, s);
            ivec2 px = base + ivec2(k & 3u, k >> 2);
            if (any(lessThan(px, ivec2(0))) || any(greaterThanEqual(px, full)))
                continue; // outside the image (the first blocks and odd sizes)
            vec4 pos = imageLoad(gPosition, px);
            if (pos.w == 0.0) {
                background |= 1u << uint(s);
                continue;
            }
            vec3 n = normalize(imageLoad(gNormal, px).xyz);
            ivec2 taps[4];
            vec4 w;
            lowResTapCell(px, f, low, taps, w);
            vec4 off;
            bvec4 fits;
            if (lowResTapsEdge(pos.xyz, n, distance(pos.xyz, pc.eye.xyz), pc.eye.w, q, nq, w, off, fits)) {
                edges |= 1u << uint(s);
                continue;
            }
            imageStore(outIndirect, px, radianceAt(px, w[0] * li[0] + w[1] * li[1] + w[2] * li[2] + w[3] * li[3],
                                                   w[0] * lg[0] + w[1] * lg[1] + w[2] * lg[2] + w[3] * lg[3]));
        }
        // The background, and the glossy image where requested, in loops of their own (a masked
        // store in the loop above cost every pixel).
        for (uint b = background; b != 0u; b &= b - 1u) {
            uint k = blockPixel(f, c, findLSB(b));
            imageStore(outIndirect, base + ivec2(k & 3u, k >> 2), vec4(0.0, 0.0, 0.0, 1.0));
        }
        for (int s = 0; s < (glossyImage ? f * f : 0); ++s) {
            uint k = blockPixel(f, c, s);
            ivec2 px = base + ivec2(k & 3u, k >> 2);
            if ((edges & (1u << uint(s))) != 0u || any(lessThan(px, ivec2(0))) || any(greaterThanEqual(px, full)))
                continue; // the edge pixels' glossy comes below
            ivec2 taps[4];
            vec4 w;
            lowResTapCell(px, f, low, taps, w);
            bool bg = (background & (1u << uint(s))) != 0u;
            imageStore(outGlossy, px, bg ? vec4(0.0) : w[0] * lg[0] + w[1] * lg[1] + w[2] * lg[2] + w[3] * lg[3]);
        }
        for (; edges != 0u; edges &= edges - 1u) {
            uint k = blockPixel(f, c, findLSB(edges));
            ivec2 px = base + ivec2(k & 3u, k >> 2);
            vec4 pos = imageLoad(gPosition, px);
            vec3 n = normalize(imageLoad(gNormal, px).xyz);
            ivec2 taps[4];
            vec4 w;
            lowResTapCell(px, f, low, taps, w);
            float depth = distance(pos.xyz, pc.eye.xyz);
            bool refined =
                lowResFitTapsAt(pos.xyz, n, depth, pc.eye.w, pc.grid.originSize.w, kUpsampleReach, q, nq, w);
            // Refined pixels get these too, overwritten by the refine trace.
            imageStore(outIndirect, px, radianceAt(px, w[0] * li[0] + w[1] * li[1] + w[2] * li[2] + w[3] * li[3],
                                                   w[0] * lg[0] + w[1] * lg[1] + w[2] * lg[2] + w[3] * lg[3]));
            if (glossyImage)
                imageStore(outGlossy, px, w[0] * lg[0] + w[1] * lg[1] + w[2] * lg[2] + w[3] * lg[3]);
            if (!refined)
                continue;
            // A tap whose source pixel (traced at full resolution by the low-res trace) lies on the
            // same spot, with the same albedo and metallic, serves the pixel as a traced pixel of
            // the block would: its value is that pixel's trace.
            vec4 albedo = imageLoad(gAlbedo, px);
            int tap = -1;
            for (int j = 0; j < 4; ++j)
                if (tap < 0 && q[j].w != 0.0 && qa[j] == albedo && vctSameSpot(pos, n, q[j], nq[j]))
                    tap = j;
            if (tap >= 0) {
                vec4 ti = li[0], tg = lg[0];
                for (int j = 1; j < 4; ++j) {
                    ti = tap == j ? li[j] : ti;
                    tg = tap == j ? lg[j] : tg;
                }
                imageStore(outIndirect, px, radianceAt(px, ti, tg));
                if (glossyImage)
                    imageStore(outGlossy, px, tg);
                continue;
            }
            // In block order: the first traced pixel before this one on the same spot serves it,
            // else it is traced.
            bool served = false;
            for (int j = 0; j < kSlots; ++j) {
                if (!served && j < leaders && vctSameSpot(pos, n, leadPos[j], leadNrm[j])) {
                    leadServes[j] |= 1u << k;
                    served = true;
                }
            }
            if (served)
                continue;
            if (leaders == kSlots) {
                alone |= 1u << k;
                continue;
            }
            for (int j = 0; j < kSlots; ++j) {
                if (j == leaders) {
                    leadPos[j] = pos;
                    leadNrm[j] = n;
                    leadK[j] = k;
                    leadServes[j] = 1u << k;
                }
            }
            ++leaders;
        }
    }
    if (leaders == 0)
        return;
    uint slot = atomicAdd(refineCount, uint(leaders) + uint(bitCount(alone)));
    for (int j = 0; j < kSlots; ++j)
        if (j < leaders)
            listEntry(slot + uint(j), vctRefineEntry(base, leadK[j], leadServes[j]));
    slot += uint(leaders);
    for (; alone != 0u; alone &= alone - 1u) {
        uint k = uint(findLSB(alone));
        listEntry(slot++, vctRefineEntry(base, k, 1u << k));
    }
}
