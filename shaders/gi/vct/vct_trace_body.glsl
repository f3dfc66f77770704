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

// ---- The skipped segment (docs/vct.md "The skipped segment") ----
// A cone starts one voxel off the surface and takes its first sample one voxel further on, so it
// never reads what lies in between: a banner hanging 0.3 m in front of a pier, the far side of a
// crevice. The segment from the surface point to the first sample is marched in quarter-voxel
// steps through the voxelizer's half-voxel occupancy (the normal volume's alpha, gi/voxel_grid.h),
// from where a half voxel no longer reaches back to the surface's own plane; a cone that meets an
// occupied half voxel ends there and takes that voxel's light along the cone (its view of the
// level-0 directional volume: the face the cone meets). Read in the grid, or in the clipmap level
// whose voxels the cones start from when that is level 0 or 1 (testing the coarser levels too
// made `atrium_world` worse). A grid without the bits (dims.z = 0: tests' own grids) stores an
// occupied voxel's alpha as 1, i.e. all eight halves set: there the test is per whole voxel.
layout(set = 1, binding = VCT_TRACE_BINDING_OCCUPANCY, rgba8) uniform readonly image3D occupancyFine;
#ifdef GI_VCT_CLIPMAP
layout(set = 1, binding = VCT_TRACE_BINDING_OCCUPANCY_COARSE, rgba8) uniform readonly image3D occupancyCoarse;
#endif
// Per pixel: whether to test, the surface point and the first sample's distance (finest voxels,
// the grid's voxels without a clipmap), and the tested clipmap level.
bool skipTest = false;
vec3 skipSurface = vec3(0.0);
float skipStart = 1.0;
int skipLevel = 0;
vec3 skipHit = vec3(0.0); // where the last blocked segment met a surface (the tested level's voxels)

// Both defined below the cone tracers (the clipmap's levels, the volume's sampling), called from
// their gathers.
bool skippedSurface(vec3 origin, vec3 d, vec3 normal);
vec3 skippedLight(vec3 d);
#define VCT_SKIPPED_CONE(origin, d, normal)                                                       \
    if (skipTest && skippedSurface(origin, d, normal)) {                                          \
        sum += skippedLight(d);                                                                   \
        occlusion += 1.0;                                                                         \
        continue;                                                                                 \
    }

#include "voxel_cone.glsl"
#ifdef GI_VCT_CLIPMAP
#include "voxel_clip.glsl"
#endif

bool skippedSurface(vec3 origin, vec3 d, vec3 normal) {
#ifdef GI_VCT_CLIPMAP
    vec3 corner = clip.level[skipLevel].xyz;
    float voxel = clip.level[skipLevel].w;
#else
    vec3 corner = vec3(0.0);
    float voxel = 1.0;
#endif
    vec3 s = (skipSurface - corner) / voxel;
    vec3 q = (origin + skipStart * d - corner) / voxel;
    int steps = int(ceil(4.0 * length(q - s)));
    // A half voxel of side 1/2 around a point h above the plane reaches below it up to
    // h < |n|_1 / 2: such points may lie in the surface's own half voxels.
    float clear = 0.5 * (abs(normal.x) + abs(normal.y) + abs(normal.z));
    int n = int(pc.grid.dims.x);
    for (int i = 1; i <= steps; ++i) {
        vec3 x = mix(s, q, float(i) / float(steps));
        ivec3 c = ivec3(floor(x));
        if (dot(x - s, normal) < clear || any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, ivec3(n))))
            continue;
#ifdef GI_VCT_CLIPMAP
        float a = skipLevel == 0 ? imageLoad(occupancyFine, c).a : imageLoad(occupancyCoarse, c).a;
#else
        float a = imageLoad(occupancyFine, c).a;
#endif
        ivec3 h = min(ivec3(2.0 * (x - vec3(c))), ivec3(1));
        if ((voxelHalfBits(a) & (1u << uint(h.x + 2 * h.y + 4 * h.z))) != 0u) {
            skipHit = vec3(c) + 0.5; // the voxel alone, not filtered with its neighbours
            return true;
        }
    }
    return false;
}

// The light a cone blocked at skipHit meets: the voxel's view along d (level 0 of the tested
// grid, the texel holding the point), its radiance = rgb over the optical depth.
vec3 skippedLight(vec3 d) {
    ConeFrame f = coneFrame(d, float(pc.grid.dims.x));
#ifdef GI_VCT_CLIPMAP
    float layerBase = float(GI_VCT_DIRECTIONS * uint(skipLevel)) * f.n;
#else
    float layerBase = 0.0;
#endif
    vec4 s = sampleDirectionalAt(f, skipHit, 0, 1.0, false, layerBase);
    return s.a > 0.0 ? s.rgb / s.a : vec3(0.0);
}
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
    skipLevel = findMSB(int(start)); // the lift is the voxel of the level the cones start from
    skipTest = skipLevel < 2;
    skipSurface = u;
    skipStart = start;
#define VCT_DIFFUSE_GATHER(TURN, OCCLUSION) diffuseGatherClip(p, normal, pc.cones, start, TURN, OCCLUSION)
#else
    float n = float(pc.grid.dims.x);
    vec3 p = (position.xyz - pc.grid.originSize.xyz) * pc.grid.scales.x + normal;
    skipTest = true;
    skipSurface = p - normal;
    skipStart = kConeStart;
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
