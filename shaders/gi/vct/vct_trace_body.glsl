// Per-pixel voxel cone tracing over the G-buffer (vct_trace.comp, vct_trace_refine.comp):
// diffuse cones over the normal hemisphere, a glossy cone along the mirror direction whose
// aperture follows the roughness, and cone-traced AO. Output radiance is in nits
// (radianceScale undone). With a low-res factor f > 1 the plain variant fills the low-res
// images from every f-th pixel (gi/lowres_upsample.h) with the incoming light (diffuse and
// glossy cones, no albedo); vct_upsample.comp interpolates them, applies each pixel's own albedo
// and metallic, and lists the pixels across discontinuities, which the refine variant
// (GI_VCT_REFINE) traces at full resolution.
#include "gi/vct_passes.h"
#ifndef GI_VCT_REFINE
#define GI_LOWRES_SOURCE_ONLY
#include "gi/lowres_upsample.h"
#endif

#ifdef GI_VCT_REFINE
layout(local_size_x = GI_VCT_REFINE_GROUP) in; // indirect: header words 1..3 (vct_upsample.comp)
#else
layout(local_size_x = 8, local_size_y = 8) in;
#endif
layout(push_constant) uniform Push { VctTracePush pc; };
#include "voxel_cone.glsl"
#ifdef GI_VCT_CLIPMAP
#include "voxel_clip.glsl"
#endif
layout(set = 1, binding = VCT_TRACE_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(set = 1, binding = VCT_TRACE_BINDING_NORMAL, rgba16f) uniform readonly image2D gNormal;
layout(set = 1, binding = VCT_TRACE_BINDING_ALBEDO, rgba16f) uniform readonly image2D gAlbedo;
layout(set = 1, binding = VCT_TRACE_BINDING_INDIRECT, rgba32f) uniform writeonly image2D outIndirect; // rgb indirect, a = AO
layout(set = 1, binding = VCT_TRACE_BINDING_GLOSSY, rgba32f) uniform writeonly image2D outGlossy;   // rgb glossy cone radiance
#ifdef GI_VCT_REFINE
layout(set = 1, binding = VCT_TRACE_BINDING_REFINE_LIST, std430) readonly buffer RefineList {
    uint refineCount;
    uint refinePad[3];
    uvec2 refineEntries[]; // vctRefineEntry
};
#include "vct_refine.glsl"
#else
// The refine list's header, zeroed here for the upsample (which appends) and the refine (an
// indirect dispatch of its groups): count 0, groups {0, 1, 1}. Saves a pass.
layout(set = 1, binding = VCT_TRACE_BINDING_REFINE_LIST, std430) writeonly buffer RefineList {
    uvec4 refineHeader;
};
#endif

void main() {
    ivec2 full = ivec2(pc.cones.info.zw);
    bool incoming = (pc.cones.info.y & GI_VCT_FLAG_INCOMING) != 0u;
    // The filter's column pass reads the glossy light too.
    bool glossyImage = (pc.cones.info.y & GI_VCT_FLAG_GLOSSY_IMAGE) != 0u || incoming;
#ifdef GI_VCT_REFINE
    if (gl_GlobalInvocationID.x >= min(refineCount, pc.lowRes.w))
        return;
    uvec2 entry = refineEntries[gl_GlobalInvocationID.x];
    uint leader = vctRefineIndex(entry);
    ivec2 dst = vctRefinePixel(entry);
    ivec2 px = dst;
#else
    if (gl_GlobalInvocationID.xy == uvec2(0u))
        refineHeader = uvec4(0u, 0u, 1u, 1u);
    ivec2 dst = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(dst, ivec2(pc.lowRes.yz))))
        return;
    ivec2 px = lowResSource(dst, int(pc.lowRes.x), full);
#endif
    vec4 position = imageLoad(gPosition, px);
    if (position.w == 0.0) {
        imageStore(outIndirect, dst, vec4(0.0, 0.0, 0.0, 1.0));
        if (glossyImage)
            imageStore(outGlossy, dst, vec4(0.0));
        return;
    }
    vec4 nr = imageLoad(gNormal, px);
    vec4 am = imageLoad(gAlbedo, px);
    vec3 normal = normalize(nr.xyz);
    // Rotated cone sets (docs/vct.md "Rotated cone sets"): with the filter on, the diffuse cones
    // turn about the normal, by one of 4 angles (k + 1/2) pi/2 in a 2 x 2 pattern of low-res
    // texels in the low-res trace, and by 0 or pi in a checkerboard of pixels where every pixel
    // is traced at full resolution (f = 1). Each pixel's set is still a whole estimate; the
    // filter's window averages the pattern, so the light no longer follows tangentFrame's
    // azimuth, which whirls around n = +-z: a curved surface facing a camera that looks along -z
    // showed a bright blotch there. Refined pixels lie mostly along edges and silhouettes, where
    // the window is cut short and cannot average a pattern: each traces both sets, at 0 and pi.
    bool rotate = (pc.cones.info.y & GI_VCT_FLAG_ROTATE) != 0u;
    float turn = 0.0;
#ifndef GI_VCT_REFINE
    if (rotate) {
        bool lowTrace = pc.lowRes.x > 1u;
        ivec2 cell = (lowTrace ? dst : px) & 1;
        turn = lowTrace ? 1.57079633 * (float((cell.x * 2) ^ (cell.y * 3)) + 0.5) // opposite turns side by side
                        : 3.14159265 * float((cell.x + cell.y) & 1);
    }
#endif
#ifdef GI_VCT_CLIPMAP
    // In finest voxels from level 0's corner (pc.grid is level 0), lifted one voxel of the
    // coarsest level the first samples read.
    vec3 u = (position.xyz - pc.grid.originSize.xyz) * pc.grid.scales.x;
    float start = clipLift(u);
    vec3 p = u + start * normal;
#define VCT_DIFFUSE_GATHER(TURN, OCCLUSION) diffuseGatherClip(p, normal, pc.cones, start, TURN, OCCLUSION)
#else
    float n = float(pc.grid.dims.x);
    vec3 p = (position.xyz - pc.grid.originSize.xyz) * pc.grid.scales.x + normal;
#define VCT_DIFFUSE_GATHER(TURN, OCCLUSION) diffuseGather(p, normal, pc.cones, n, TURN, OCCLUSION)
#endif
    float occlusion;
    vec3 diffuse = VCT_DIFFUSE_GATHER(turn, occlusion);
#ifdef GI_VCT_REFINE
    if (rotate) {
        float opposite;
        diffuse = 0.5 * (diffuse + VCT_DIFFUSE_GATHER(3.14159265, opposite));
        occlusion = 0.5 * (occlusion + opposite);
    }
#endif
    vec3 glossy = vec3(0.0);
    if ((pc.cones.info.y & GI_VCT_FLAG_GLOSSY) != 0u) {
        vec3 v = normalize(pc.eye.xyz - position.xyz);
        // GGX-like lobe width alpha = roughness^2 as the cone's tan(half-angle), floored so a
        // mirror still gets a finite footprint of about a voxel at 50 voxels.
        float tanHalf = clamp(nr.w * nr.w, 0.01, 1.0);
        float unused;
        vec3 r = reflect(-v, normal);
#ifdef GI_VCT_CLIPMAP
        glossy = traceConeClip(p, r, max(dot(r, normal), 0.0), tanHalf, pc.cones.cone.y, 0.0, start, unused).rgb;
#else
        glossy = traceCone(p, r, max(dot(r, normal), 0.0), tanHalf, pc.cones.cone.y, 0.0, n, unused).rgb;
#endif
    }
    float metallic = clamp(am.w, 0.0, 1.0);
    vec3 indirect = am.rgb * mix(diffuse, glossy, metallic) * pc.grid.scales.z;
    float ao = (pc.cones.info.y & GI_VCT_FLAG_AO) != 0u ? 1.0 - occlusion : 1.0;
#ifndef GI_VCT_REFINE
    if (pc.lowRes.x > 1u || incoming) {
        // Low resolution: the incoming light without the sample's albedo and metallic, which the
        // upsample applies per full-resolution pixel (a checkered floor stays sharp); with the
        // filter, its column pass applies them (vct_filter.comp).
        imageStore(outIndirect, dst, vec4(diffuse * pc.grid.scales.z, ao));
        imageStore(outGlossy, dst, vec4(glossy * pc.grid.scales.z, 1.0));
        return;
    }
#endif
    imageStore(outIndirect, dst, incoming ? vec4(diffuse * pc.grid.scales.z, ao) : vec4(indirect, ao));
    if (glossyImage)
        imageStore(outGlossy, dst, vec4(glossy * pc.grid.scales.z, 1.0));
#ifdef GI_VCT_REFINE
    // The refined pixels of this block that take this trace (the upsample's mask,
    // vct_refine.glsl), with their own albedo and metallic.
    uint serves = vctRefineServes(entry) & ~(1u << leader);
    ivec2 base = dst - ivec2(leader & 3u, leader >> 2);
    while (serves != 0u) {
        int k = findLSB(serves);
        serves &= serves - 1u;
        ivec2 q = base + ivec2(k & 3, k >> 2);
        vec4 aq = imageLoad(gAlbedo, q);
        vec3 iq = incoming ? diffuse * pc.grid.scales.z
                           : aq.rgb * mix(diffuse, glossy, clamp(aq.w, 0.0, 1.0)) * pc.grid.scales.z;
        imageStore(outIndirect, q, vec4(iq, ao));
        if (glossyImage)
            imageStore(outGlossy, q, vec4(glossy * pc.grid.scales.z, 1.0));
    }
#endif
}
