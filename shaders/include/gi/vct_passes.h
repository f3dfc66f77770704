// Shader interface of the voxel cone tracing passes (C++ and GLSL): the directional volume,
// the occupied-voxel list, the second bounce's buffers, push constants and bindings. Each push
// block stays within lavapipe's 128-byte limit; sizes are pinned on both sides.
#ifndef VKGI_GI_VCT_PASSES_H
#define VKGI_GI_VCT_PASSES_H
#include "voxel_passes.h"

GI_NAMESPACE_BEGIN

// The volumes of the VCT passes:
//   directional volume
//             RGBA16F 2D array, N x N texels, 6N layers, log2(N) + 1 mips: one stack of N layers
//             per viewing direction d in the order +X, -X, +Y, -Y, +Z, -Z, each layer a slice
//             across d's own axis (vctDirectionalTexel: layer d N + s for slice s along the
//             axis, 2D coordinates the other two axes in order: X views (y, z), Y views (x, z),
//             Z views (x, y)). Level k is (N >> k)^2 and uses the first N >> k layers of each
//             stack (the array keeps 6N layers at every level; the rest are never written or
//             read). Texel = what a ray travelling along that direction sees of the 2^k-voxel
//             block: rgb = outgoing radiance * radianceScale, premultiplied by a = opacity.
//             Level 0 holds the voxels themselves (the voxel light writes it per facing
//             direction, voxel_light_body.glsl), level k >= 1 the blocks, front-to-back
//             composited from level k - 1 (Crassin's pre-integration). A cone reads each view at
//             its texel's centre along the view's axis, so a view's sample is one layer filtered
//             bilinearly (4 texels, voxel_cone.glsl) where a 3D volume's trilinear fetch read 8,
//             4 of them with weight 0; lavapipe's cost grows with the texels a fetch reads. One
//             image instead of six lets a cone pick its three stacks by arithmetic, without
//             divergent branches. Empty voxels are 0. ~17% more memory than six 3D chains (8 N^3
//             texels, not 48/7 N^3).
//   bounce    RGBA16F N^3 (transient): the misfit voxels' second bounce, albedo * E / pi from
//             their own gathers (voxel_bounce_misfits.comp), read by the apply
//             (voxel_bounce_apply.comp), which adds every voxel's to its level-0 views.
#define GI_VCT_DIRECTIONS 6
// Texel (x, y, layer) of the directional volume holding view d (0..5) of voxel or block c at
// any level; n = N (the level-0 resolution: every level keeps N layers per view).
GI_INLINE ivec3 vctDirectionalTexel(ivec3 c, uint d, uint n) {
    uint axis = d >> 1u;
    ivec3 t = axis == 0u ? ivec3(c.y, c.z, c.x) : (axis == 1u ? ivec3(c.x, c.z, c.y) : c);
    return t + ivec3(0, 0, int(d * n));
}


// Occupied-voxel list (voxel_compact.comp, rebuilt once per voxelization from the touched
// lists): a storage buffer of GI_VOXEL_LIST_HEADER uints, then N^3 slots for occupied voxels,
// then (N/2)^3 slots for occupied 2^3 blocks, each a packed coordinate, then N^3 / 32 + (N/2)^3 / 32
// words of "already listed" bits (voxels, then blocks: a dynamic voxel inside a static one and
// the 2^3 blocks are listed once), then ceil((N/4)^3 / 32) words of 4^3-block occupancy bits
// (the voxel light's march skips empty 4^3 blocks), all zeroed with the header. Header words 0..3 belong to the
// voxels, 4..7 to the blocks; each quad is also the VkDispatchIndirectCommand (at byte 0 and
// 16) of the passes that run over that list: x = ceil(count / GI_VOXEL_LIST_GROUP) work
// groups, y = z = 1, w = count. Surface voxels are ~10% of a grid, so those passes skip the
// empty 90% without divergent lanes.
#define GI_VOXEL_LIST_HEADER 8u
#define GI_VOXEL_LIST_BLOCKS 4u // header offset (words) of the block quad
// Word offset (after the header) of the voxels' "listed" bits, bit x + N (y + N z): once the
// list is built, the grid's occupancy, 32 voxels per word (the voxel light's march reads it).
GI_INLINE uint voxelListBitsOffset(uint n) { return n * n * n + (n / 2u) * (n / 2u) * (n / 2u); }
// Word offset (after the header) of the 4^3-block occupancy bits, bit x + N/4 (y + N/4 z).
GI_INLINE uint voxelListCoarseBitsOffset(uint n) { return voxelListBitsOffset(n) + voxelListBitsOffset(n) / 32u; }
// Words after the header.
GI_INLINE uint voxelListWords(uint n) { return voxelListCoarseBitsOffset(n) + ((n / 4u) * (n / 4u) * (n / 4u) + 31u) / 32u; }

// The axes k whose two level-0 views (2k, 2k + 1) the voxel light stores for a voxel with packed
// faces `faces` (voxel_grid.h), bit k each: those with coverage along k (opacity > 0; the views
// along an axis the voxel's sheets are edge-on to stay 0), all three for an occupied voxel
// without coverage (opacity 1). Never 0 for an occupied voxel.
GI_INLINE uint voxelViewAxes(uint faces) {
    uint axes = 0u;
    for (uint k = 0u; k < 3u; ++k)
        axes |= ((faces >> (10u * k)) & 1023u) != 0u ? 1u << k : 0u;
    return axes != 0u ? axes : 7u;
}
// What levels 0 and 1 of the directional volume hold from the last voxelizations, so that a
// voxelization zeroes only what went stale instead of clearing both levels (both zeroed with these at the first):
//   written       R8UI N^3: the voxelViewAxes each voxel's level-0 views were last stored with (0:
//                 none stored). The voxel light compares it with the voxel's faces and zeroes the
//                 views along the axes it no longer stores (voxel_light_body.glsl);
//   written bits  a storage buffer of the last list's voxel and block bits ((N^3 + (N/2)^3) / 32
//                 words, the list's layout): voxel_list_stale.comp zeroes the views of the voxels
//                 listed then and not now (and their `written`) and the level-1 views of such blocks.
GI_INLINE uint voxelWrittenBitsWords(uint n) { return voxelListBitsOffset(n) / 32u; }

// Occlusion of voxel direct light (VctOcclusion).
#define GI_VCT_OCCLUSION_HARD 0u
#define GI_VCT_OCCLUSION_SOFT 1u
#define GI_VCT_OCCLUSION_SHADOW_MAP 2u

// voxel_light.comp: direct light + emission per occupied voxel. The voxels in the box keepLo ..
// keepHi (inclusive, grid voxels; empty when lo > hi) kept their views across a clipmap level's
// move (shifted in by gi.vct.shift): they only restore their "written" record.
GI_GPU_STRUCT(VoxelLightPush) {
    VoxelGridParams grid;
    uvec4 info; // x light count, y occlusion mode (GI_VCT_OCCLUSION_*), z flags (GI_VOXEL_LIGHT_*), w 1 + the
                // shadow window of directional lights fitted to this grid (GpuLightShadow), 0 none
    ivec4 keepLo;
    ivec4 keepHi;
};
GI_CHECK_SIZE(VoxelLightPush, 96);
#define GI_VOXEL_LIGHT_EMISSION 1u // add the emission volume (the voxels' emission injection)

// voxel_mip.comp: builds level `info.x` >= 1 of the directional volume from level info.x - 1;
// voxel_mip_tail.comp levels info.x .. info.x + info.z - 1 (the last ones, info.y <= 8) in one
// work group.
// voxel_mip_list_jobs.comp also skips the bounce blocks whose voxels and neighbour blocks all lie
// in the box keepLo .. keepHi (inclusive grid voxels; empty when lo > hi): the voxels a moved
// clipmap level kept, which keep their second bounce (voxel_bounce_apply.comp).
GI_GPU_STRUCT(VoxelMipPush) {
    VoxelGridParams grid;
    uvec4 info; // x (first) destination level, y its resolution, z level count (tail), w 0
    ivec4 keepLo;
    ivec4 keepHi;
};
GI_CHECK_SIZE(VoxelMipPush, 96);
// voxel_bounce_apply.comp: the voxels in keepLo.xyz .. keepHi.xyz (empty when lo > hi) take their
// bounce from the kept one (VCT_APPLY_BINDING_KEPT) instead of the gathers; keepHi.w holds
// GI_VCT_APPLY_* flags: STORE stores every voxel's bounce (VCT_APPLY_BINDING_BOUNCE: a clipmap
// level keeps it for its next move, a third bounce subtracts it), without it that binding is left
// unwritten (the fitted grid with two bounces binds a 1^3 stand-in); ADDED says level 0 already
// holds the stored bounce (the third bounce's apply), so only the difference is added.
GI_GPU_STRUCT(VoxelApplyPush) {
    VoxelGridParams grid;
    ivec4 keepLo;
    ivec4 keepHi;
};
GI_CHECK_SIZE(VoxelApplyPush, 80);
#define GI_VCT_APPLY_STORE 1
#define GI_VCT_APPLY_ADDED 2

// Cone parameters shared by the per-voxel bounce and the per-pixel trace.
GI_GPU_STRUCT(ConeParams) {
    vec4 cone;  // x tan(diffuse half-angle), y step factor, z AO decay (1/voxels), w tan(shadow half-angle)
    uvec4 info; // x diffuse cone count, y flags (GI_VCT_FLAG_*), z width, w height
};
#define GI_VCT_FLAG_GLOSSY 1u
#define GI_VCT_FLAG_AO 2u
#define GI_VCT_FLAG_GLOSSY_IMAGE 4u // the glossy images are written (FrameRequest::glossy)
// The trace writes the incoming light (no albedo) at f = 1 too: vct_filter.comp applies it.
#define GI_VCT_FLAG_INCOMING 8u
// The diffuse cone set turns about the normal in a pattern over the traced pixels, which the
// filter averages (vct_trace_body.glsl, docs/vct.md "Rotated cone sets"); set with the filter.
#define GI_VCT_FLAG_ROTATE 16u

// Second bounce (voxel_bounce*.comp, docs/vct.md "Second bounce"): one diffuse gather per
// (occupied block of bounceBlockSide()^3 voxels, normal class), a class being one of the 26 directions of a cube's faces,
// edges and corners nearest to the voxel normal (voxelNormalClass, voxel_block.glsl). The job
// buffer (one per grid, rewritten every relit frame) holds, in uints:
//   header  GI_BOUNCE_HEADER words: 0..3 the gathers' VkDispatchIndirectCommand (x =
//           ceil(largest class count / GI_VOXEL_LIST_GROUP), y = GI_BOUNCE_CLASSES: work group
//           row k runs class k's jobs, so the SIMD lanes of a group trace the same directions),
//           4..7 the misfit voxels' (normal more than 25 degrees from their class's mean: they
//           gather their own cones) as the occupied lists' quads (x = ceil(count / group), y = z
//           = 1, w = count), then GI_BOUNCE_CLASSES job counts, one per class;
//   then (words after the header, offsets below) per block (x + Q (y + Q z), Q = N / side) the
//   26-bit mask of the classes present; the jobs of class k (block index each) from
//   k * Q^3 on; the misfit voxels, voxelListPack each; one misfit bit per voxel, two words
//   per 4^3 block (bounceMisfitBit), zeroed by the clear, set by the gathers, read by the apply;
//   per (block b, class k) at bounceGeometryOffset + GI_BOUNCE_GEOMETRY (26 b + k) the sums over
//   the class's voxels that the job listing adds (voxel_mip_body.glsl) and the gathers read:
//   count | (sum of x - block x) << 10, (sum of y - block y) | (sum of z - block z) << 16, the
//   largest and the complement of the smallest of their normals' bytes (voxelNormalBytes: equal
//   when all store the same normal), the largest dot(c, normal) (orderedFromFloat).
// Only the header is cleared; the masks and misfit bits of all blocks are written, the rest
// before it is read.
// The gathers' results go to a second buffer (one storage buffer of both would exceed
// lavapipe's maxStorageBufferRange at 256^3): 2 words per (block b, class k) at 2 (26 b + k),
// packHalf2x16 of r, g and of b, 0: (1/n) sum L_i.
#define GI_BOUNCE_CLASSES 26u
#define GI_BOUNCE_COUNTS 8u // header offset (words) of the per-class job counts
#define GI_BOUNCE_HEADER (GI_BOUNCE_COUNTS + GI_BOUNCE_CLASSES)
#define GI_BOUNCE_MISFITS 4u // header offset (words) of the misfit quad
// Side of a block (voxels): 8 from 64^3 on, 4 below (a block at most 1/8 of the grid: the
// room's second bounce at 32^3 with 8-voxel blocks, 1.6 m, had 1.3x the indirect error).
GI_INLINE uint bounceBlockSide(uint n) { return n >= 64u ? 8u : 4u; }
GI_INLINE uint bounceBlockCount(uint n) {
    uint side = n / bounceBlockSide(n);
    return side * side * side;
}
GI_INLINE uint bounceJobOffset(uint n) { return bounceBlockCount(n); }
GI_INLINE uint bounceMisfitOffset(uint n) { return bounceJobOffset(n) + GI_BOUNCE_CLASSES * bounceBlockCount(n); }
GI_INLINE uint bounceMisfitBitsOffset(uint n) { return bounceMisfitOffset(n) + n * n * n; }
// Word (x, relative to bounceMisfitBitsOffset) and bit (y) of voxel c's misfit bit: the 64 voxels
// of a 4^3 block share two consecutive words (the job pass zeroes them per 4^3 block).
GI_INLINE uvec2 bounceMisfitBit(uvec3 c, uint n) {
    uint b4 = (c.x >> 2u) + (n >> 2u) * ((c.y >> 2u) + (n >> 2u) * (c.z >> 2u));
    uint v = (c.x & 3u) + 4u * (c.y & 3u) + 16u * (c.z & 3u);
    return uvec2(2u * b4 + (v >> 5u), v & 31u);
}
#define GI_BOUNCE_GEOMETRY 5u // words per (block, class) of the sums over its voxels
GI_INLINE uint bounceGeometryOffset(uint n) { return bounceMisfitBitsOffset(n) + n * n * n / 32u; }
GI_INLINE uint bounceGeometryWords(uint n) { return GI_BOUNCE_GEOMETRY * GI_BOUNCE_CLASSES * bounceBlockCount(n); }
// Words after the header (misfits: at most every voxel; misfit bits: one per voxel).
GI_INLINE uint bounceJobWords(uint n) { return bounceGeometryOffset(n) + bounceGeometryWords(n); }
GI_INLINE uint bounceResultWords(uint n) { return 2u * GI_BOUNCE_CLASSES * bounceBlockCount(n); }

// voxel_bounce*.comp: the grid and the diffuse cones.
GI_GPU_STRUCT(VoxelBouncePush) {
    VoxelGridParams grid;
    ConeParams cones;
    // x the gathering level (clipmap variants, voxel_bounce*_clip.comp), y 1 when an earlier
    // bounce's gathers already listed the misfits (the third bounce), zw 0
    uvec4 clip;
};
GI_CHECK_SIZE(VoxelBouncePush, 96);

// vct_trace*.comp, vct_upsample.comp: per-pixel cones over the G-buffer (cones.info.zw =
// full-res size), optionally at 1/f resolution with a discontinuity refine.
GI_GPU_STRUCT(VctTracePush) {
    VoxelGridParams grid;
    ConeParams cones;
    vec4 eye;     // xyz camera position (world), w refine threshold (gi/lowres_upsample.h)
    uvec4 lowRes; // x factor f, y, z low-res width, height, w refine-list capacity (pixels)
};
GI_CHECK_SIZE(VctTracePush, 112);

// vct_filter.comp: one axis of the geometry-aware tent (gi/surface_filter.h) over the trace's
// incoming diffuse light (a = AO) at the trace's resolution (docs/vct.md "Filter").
GI_GPU_STRUCT(VctFilterPush) {
    vec4 eye;   // xyz camera position (world), w tangent-plane tolerance (fraction of the depth)
    uvec4 size; // x, y trace-image width, height; z factor f; w tent side n
    uvec4 info; // x axis (0 rows, 1 columns); y 1: apply albedo and metallic (f = 1, columns); z, w full-res size
};
GI_CHECK_SIZE(VctFilterPush, 48);

// vct_soft_shadow.comp: direct light of the punctual lights over the G-buffer with cone-traced
// visibility (cones.cone.w = tan(shadow half-angle)) instead of the shadow atlas.
GI_GPU_STRUCT(VctShadowPush) {
    VoxelGridParams grid;
    ConeParams cones;
    uvec4 info; // x light count, y width, z height, w 0
};
GI_CHECK_SIZE(VctShadowPush, 96);
// Clipmap (VctSettings::levels > 1, docs/vct.md "Clipmap"): level l is an N^3 grid of voxels
// 2^l times the finest, its own directional volume copied into the clipmap volume, the same 2D
// array with the levels stacked along the layers: level l's stack of view d starts at layer
// (GI_VCT_DIRECTIONS l + d) N, mips as in the directional volume. The per-pixel cones
// (vct_trace_clip.comp, voxel_clip.glsl) read it with these parameters in a uniform block.
#define GI_VCT_MAX_LEVELS 8u
GI_GPU_STRUCT(VctClipmapParams) {
    // Per level: xyz its min corner in finest voxels from level 0's (whole numbers minus
    // (2^l - 1) / 2: each level's voxels are centred on its own lattice, worldVoxelCorner), w 2^l.
    vec4 level[GI_VCT_MAX_LEVELS];
    uvec4 info; // x level count, y N, z 0, w 0
};
GI_CHECK_SIZE(VctClipmapParams, 144);

// Refine list (vct_upsample.comp -> vct_trace_refine.comp): uint count, then the refine
// trace's VkDispatchIndirectCommand (groups of GI_VCT_REFINE_GROUP), then the traced pixels
// (vctRefineEntry in shaders/gi/vct/vct_refine.glsl: quad, pixel in it, pixels it serves).
#define GI_VCT_REFINE_GROUP 64u
#define GI_VCT_REFINE_HEADER 4u

// Bindings (set 1).
// Occupied-voxel list (voxel_compact.comp, voxel_list_append.comp, voxel_list_stale.comp).
#define VCT_COMPACT_BINDING_TOUCHED 0      // a touched list of the grid (gi/voxel_passes.h), indirect over it
#define VCT_COMPACT_BINDING_LIST 1         // the occupied-voxel list: bits set, voxels and blocks appended
#define VCT_APPEND_BINDING_LIST 1          // the occupied-voxel list: its bits -> its entries in grid order
#define VCT_STALE_BINDING_LIST 0           // the new occupied-voxel list
#define VCT_STALE_BINDING_WRITTEN_BITS 1   // the last list's bits, replaced by the new list's
#define VCT_STALE_BINDING_WRITTEN 2        // the "written" volume (R8UI)
#define VCT_STALE_BINDING_LEVEL0 3         // level 0 of the directional volume (stale views zeroed)
#define VCT_STALE_BINDING_LEVEL1 4         // level 1 of the directional volume (stale blocks zeroed)
// Voxel direct light (voxel_light*.comp, voxel_light_body.glsl).
#define VCT_LIGHT_BINDING_LIGHTS 0         // GpuLight records (engine/lights.h)
#define VCT_LIGHT_BINDING_EMISSION 3       // the grid's emission volume
#define VCT_LIGHT_BINDING_OCCUPANCY 4      // the grid's albedo volume (a = occupancy): sampled by the soft march, loaded otherwise
#define VCT_LIGHT_BINDING_DIRECTIONAL 5    // level 0 of the directional volume (the listed voxels' views)
#define VCT_LIGHT_BINDING_LIST 6           // the occupied-voxel list the indirect dispatch runs over
#define VCT_LIGHT_BINDING_LIGHT_SHADOWS 7  // shadow map variant: GpuLightShadow per light (gi/direct_types.h)
#define VCT_LIGHT_BINDING_SHADOW_VIEWS 8   // shadow map variant: GpuShadowView per atlas layer
#define VCT_LIGHT_BINDING_SHADOW_ATLAS 9   // shadow map variant: the depth atlas, its stored depths gathered (point sampler)
#define VCT_LIGHT_BINDING_FACES 10         // the grid's faces volume
#define VCT_LIGHT_BINDING_WRITTEN 11       // the "written" volume (read and updated)
#define VCT_LIGHT_BINDING_LIST_WORDS 12    // hard march: the occupied-voxel list as R32UI texels
// Directional mips (voxel_mip*.comp, voxel_mip_body.glsl).
#define VCT_MIP_BINDING_SOURCE 0           // level k - 1 of the directional volume
#define VCT_MIP_BINDING_TARGET 1           // level k (voxel_mip.comp, voxel_mip_list*.comp)
#define VCT_MIP_BINDING_TAIL 1             // voxel_mip_tail.comp: levels k .. k + 3 at TAIL + 0 .. 3
#define VCT_MIP_BINDING_LIST 2             // level 1: the occupied-voxel list (its block quad is the dispatch)
#define VCT_MIP_BINDING_NORMAL 3           // level 1 with jobs: the grid's normal volume
#define VCT_MIP_BINDING_JOBS 4             // level 1 with jobs: the second bounce's job buffer
#define VCT_MIP_BINDING_FACES 5            // level 1 with jobs: the grid's faces volume (the sides of voxels without a normal)
// Cone tracing (voxel_cone.glsl): every shader that traces cones samples the directional volume here.
#define VCT_CONE_BINDING_DIRECTIONAL 1
// Second bounce (voxel_bounce*.comp).
#define VCT_BOUNCE_BINDING_NORMAL 2        // voxel_bounce.comp: the grid's normal volume
#define VCT_BOUNCE_BINDING_JOBS 3          // the job buffer (the misfit list appended)
#define VCT_BOUNCE_BINDING_RESULTS 4       // the gathers' results
#define VCT_BOUNCE_BINDING_LIST 5          // the occupied-voxel list
#define VCT_BOUNCE_BINDING_FACES 6         // the grid's faces volume (the sides of voxels without a normal)
#define VCT_MISFITS_BINDING_ALBEDO 2       // voxel_bounce_misfits.comp: the grid's albedo volume
#define VCT_MISFITS_BINDING_NORMAL 3       // the grid's normal volume
#define VCT_MISFITS_BINDING_OUTPUT 4       // the misfit voxels' bounce (RGBA16F N^3)
#define VCT_MISFITS_BINDING_JOBS 5         // the job buffer (the misfit quad is the dispatch)
#define VCT_APPLY_BINDING_ALBEDO 0         // voxel_bounce_apply.comp: the grid's albedo volume
#define VCT_APPLY_BINDING_NORMAL 1         // the grid's normal volume
#define VCT_APPLY_BINDING_JOBS 2           // the job buffer (class masks, misfit bits)
#define VCT_APPLY_BINDING_MISFITS 3        // the misfit voxels' bounce
#define VCT_APPLY_BINDING_LIST 4           // the occupied-voxel list the indirect dispatch runs over
#define VCT_APPLY_BINDING_RESULTS 5        // the gathers' results
#define VCT_APPLY_BINDING_FACES 6          // the grid's faces volume (views; the sides of voxels without a normal)
#define VCT_APPLY_BINDING_DIRECTIONAL 7    // level 0 of the directional volume (the bounce added)
#define VCT_APPLY_BINDING_KEPT 8           // a moved clipmap level's second bounce of before the move, shifted
#define VCT_APPLY_BINDING_BOUNCE 9         // every listed voxel's second bounce (RGBA32UI: rgb float bits, or its sides' rgb9e5), kept for the next move
// Per-pixel passes (vct_trace*.comp, vct_soft_shadow.comp, vct_upsample.comp).
#define VCT_TRACE_BINDING_POSITION 2       // G-buffer position (RGBA32F)
#define VCT_TRACE_BINDING_NORMAL 3         // G-buffer normal (RGBA16F, w = roughness)
#define VCT_TRACE_BINDING_ALBEDO 4         // G-buffer albedo (RGBA16F, w = metallic)
#define VCT_TRACE_BINDING_INDIRECT 5       // out: rgb indirect radiance, a = AO (RGBA32F)
#define VCT_TRACE_BINDING_GLOSSY 6         // out: glossy cone radiance (RGBA32F)
#define VCT_TRACE_BINDING_REFINE_LIST 7    // the refine list: header zeroed (trace) or traced (refine)
#define VCT_TRACE_BINDING_CLIPMAP 8        // clipmap variants (trace, refine, bounce gathers): VctClipmapParams (uniform block)
#define VCT_TRACE_BINDING_OCCUPANCY 9      // trace, refine: the grid's (clipmap: level 0's) normal volume
#define VCT_TRACE_BINDING_OCCUPANCY_COARSE 10 // clipmap trace, refine: level 1's normal volume
#define VCT_SHADOW_BINDING_POSITION 2      // G-buffer position
#define VCT_SHADOW_BINDING_NORMAL 3        // G-buffer normal
#define VCT_SHADOW_BINDING_ALBEDO 4        // G-buffer albedo
#define VCT_SHADOW_BINDING_EMISSION 5      // G-buffer emission
#define VCT_SHADOW_BINDING_LIGHTS 6        // GpuLight records
#define VCT_SHADOW_BINDING_DIRECT 7        // out: direct light with cone-traced shadows (RGBA32F)
#define VCT_UPSAMPLE_BINDING_POSITION 0    // G-buffer position
#define VCT_UPSAMPLE_BINDING_NORMAL 1      // G-buffer normal
#define VCT_UPSAMPLE_BINDING_LOW_INDIRECT 2 // the trace's low-resolution indirect image
#define VCT_UPSAMPLE_BINDING_LOW_GLOSSY 3  // the trace's low-resolution glossy image
#define VCT_UPSAMPLE_BINDING_INDIRECT 4    // out: full-resolution indirect
#define VCT_UPSAMPLE_BINDING_GLOSSY 5      // out: full-resolution glossy
#define VCT_UPSAMPLE_BINDING_REFINE_LIST 6 // the refine list (pixels appended)
#define VCT_UPSAMPLE_BINDING_ALBEDO 7      // G-buffer albedo (w = metallic)
#define VCT_FILTER_BINDING_POSITION 0      // G-buffer position
#define VCT_FILTER_BINDING_NORMAL 1        // G-buffer normal
#define VCT_FILTER_BINDING_ALBEDO 2        // G-buffer albedo (w = metallic)
#define VCT_FILTER_BINDING_INPUT 3         // the trace's (or the row pass's) incoming diffuse light, a = AO
#define VCT_FILTER_BINDING_GLOSSY 4        // the trace's incoming glossy light (applied with the albedo)
#define VCT_FILTER_BINDING_OUTPUT 5        // out: filtered incoming light, or the indirect radiance

GI_NAMESPACE_END
#endif
