// Image-space instant radiosity (Cochran & Steele): the VPL records, per-light parameters and
// the Halton sampling math, shared by C++ (gi/src/vpl) and the compute shaders (shaders/gi/vpl).
// Conventions: a VPL's flux is in cd*sr (the light's candela times the solid angle it stands
// for, times the surface albedo), so a VPL adds radiance
//     L = albedo/pi * flux/pi * cosVpl * cosReceiver / max(d^2, clampDistance^2)
// in the same nits as the direct light. Spot frames use +Z as the cone axis.
#ifndef VKGI_GI_VPL_H
#define VKGI_GI_VPL_H
#include "../shared/bridge.h"

// Most positive VPLs one light may own: the gather is O(pixels * VPLs), and 4096 is already
// far past any interactive setting.
#define GI_VPL_MAX_PER_LIGHT 4096u
// Most lights that get VPLs in one frame (the per-light parameter table is sized by it).
#define GI_VPL_MAX_LIGHTS 8u
// Most negative VPLs (paper section 3.3); same cost argument as above.
#define GI_VPL_MAX_NEGATIVE 4096u
// Largest interleave tile side (kMaxVplInterleave in vkgi/vpl.hpp): the filter reads 2n - 1
// neighbours per axis.
#define GI_VPL_MAX_INTERLEAVE 4u
// Work-group width of the 1D passes (VPL generation): 64 = 8 lavapipe SIMD lanes x 8.
#define GI_VPL_LOCAL_SIZE_1D 64
// Work-group side of the 2D passes.
#define GI_VPL_LOCAL_SIZE_2D 8

#define GI_VPL_PI 3.14159265358979f

// Bindings (set 1). The G-buffer and the RSM are point-sampled (texelFetch) through samplers.
// vpl_generate.comp: one VPL per Halton sample of each light's RSM layers.
#define VPL_GENERATE_BINDING_RSM_POSITION 0 // RSM world position (RGBA32F 2D array, w = 1 where valid)
#define VPL_GENERATE_BINDING_RSM_NORMAL 1   // RSM normal (2D array)
#define VPL_GENERATE_BINDING_RSM_FLUX 2     // RSM reflected flux (2D array)
#define VPL_GENERATE_BINDING_SHADOW_VIEWS 3 // GpuShadowView per RSM layer (gi/direct_types.h)
#define VPL_GENERATE_BINDING_LIGHTS 4       // VplLight per light
#define VPL_GENERATE_BINDING_DIRECTIONS 5   // xyz local Halton direction (or window point), w light index, subset-major
#define VPL_GENERATE_BINDING_VPLS 6         // output: VplRecord per positive VPL
// vpl_emitter.comp: the emitter source's VPLs, one per emissive surfel (gi/emissive.h).
#define VPL_EMITTER_BINDING_POSITION 0   // emissive surfel world position (RGBA32F 2D array, w = 1 where a surfel)
#define VPL_EMITTER_BINDING_NORMAL 1     // emissive surfel normal of the emitting side
#define VPL_EMITTER_BINDING_FLUX 2       // emissive surfel flux (rgb) and area (w)
#define VPL_EMITTER_BINDING_DIRECTIONS 3 // the generation table: x the surfel a sample takes, w source index
#define VPL_EMITTER_BINDING_VPLS 4       // output: VplRecord per positive VPL (the emitter source's)
// vpl_gather.comp: the positive VPLs' light at the gather resolution.
#define VPL_GATHER_BINDING_POSITION 0 // G-buffer world position (w = 1 where geometry)
#define VPL_GATHER_BINDING_NORMAL 1   // G-buffer normal
#define VPL_GATHER_BINDING_ALBEDO 2   // G-buffer albedo
#define VPL_GATHER_BINDING_VPLS 3     // VplRecord per positive VPL
#define VPL_GATHER_BINDING_INDIRECT 4 // output: indirect radiance (RGBA32F)
#define VPL_GATHER_BINDING_INCIDENT 5 // output: VPL irradiance E (the negative VPLs' flux)
#define VPL_GATHER_BINDING_TRAVEL 6   // output: luminance-weighted sum of the light's travel directions
#define VPL_GATHER_BINDING_OCCUPANCY 7 // vpl_gather_visible.comp only: the voxel grid's albedo volume (a = occupancy)
#define VPL_GATHER_BINDING_SURFACE 8   // output (interleaved): each pixel's packed surface (RGBA32UI, gi/vpl_surface.h)
#define VPL_GATHER_BINDING_VISIBILITY_MAP 9 // vpl_gather_maps.comp only: the VPLs' visibility maps (vpl_visibility_map.comp)
// vpl_interleave_rows.comp and vpl_interleave_columns.comp: the interleaved gather's subsets
// summed back over each tile (gi/vpl_interleave_filter.h), along rows, then along columns.
#define VPL_INTERLEAVE_ROWS_BINDING_SURFACE 0         // the gather's packed surfaces (gi/vpl_surface.h)
#define VPL_INTERLEAVE_ROWS_BINDING_GATHER_INCIDENT 2 // the interleaved gather's VPL irradiance (one subset, scaled)
#define VPL_INTERLEAVE_ROWS_BINDING_GATHER_TRAVEL 3   // the interleaved gather's travel directions
#define VPL_INTERLEAVE_ROWS_BINDING_INCIDENT 4        // output: irradiance filtered along rows, w subset classes
#define VPL_INTERLEAVE_ROWS_BINDING_TRAVEL 5          // output: travel directions filtered along rows
#define VPL_INTERLEAVE_COLUMNS_BINDING_SURFACE 0       // the gather's packed surfaces
#define VPL_INTERLEAVE_COLUMNS_BINDING_ALBEDO 2        // G-buffer albedo
#define VPL_INTERLEAVE_COLUMNS_BINDING_ROWS_INCIDENT 3 // the row pass's irradiance
#define VPL_INTERLEAVE_COLUMNS_BINDING_ROWS_TRAVEL 4   // the row pass's travel directions
#define VPL_INTERLEAVE_COLUMNS_BINDING_INDIRECT 5      // output: indirect radiance albedo/pi * E (RGBA32F)
#define VPL_INTERLEAVE_COLUMNS_BINDING_INCIDENT 6      // output: filtered VPL irradiance E (with negative VPLs)
#define VPL_INTERLEAVE_COLUMNS_BINDING_TRAVEL 7        // output: filtered travel directions (with negative VPLs)
#define VPL_INTERLEAVE_COLUMNS_BINDING_REFINE_LIST 8   // refine list (gi/vpl_refine_list.h), appended to at full resolution
// vpl_negative_generate.comp: negative VPLs at Halton-picked pixels of the gather image.
#define VPL_NEGATIVE_GENERATE_BINDING_POSITION 0      // G-buffer world position
#define VPL_NEGATIVE_GENERATE_BINDING_NORMAL 1        // G-buffer normal
#define VPL_NEGATIVE_GENERATE_BINDING_INCIDENT 2      // the gather's VPL irradiance
#define VPL_NEGATIVE_GENERATE_BINDING_TRAVEL 3        // the gather's travel directions
#define VPL_NEGATIVE_GENERATE_BINDING_NEGATIVE_VPLS 4 // output: VplRecord per negative VPL
// vpl_negative_gather.comp: the gather image minus the negative VPLs' light.
#define VPL_NEGATIVE_GATHER_BINDING_POSITION 0          // G-buffer world position
#define VPL_NEGATIVE_GATHER_BINDING_NORMAL 1            // G-buffer normal
#define VPL_NEGATIVE_GATHER_BINDING_ALBEDO 2            // G-buffer albedo
#define VPL_NEGATIVE_GATHER_BINDING_NEGATIVE_VPLS 3     // VplRecord per negative VPL
#define VPL_NEGATIVE_GATHER_BINDING_POSITIVE_INDIRECT 4 // the gather's indirect radiance
#define VPL_NEGATIVE_GATHER_BINDING_INDIRECT 5          // output: indirect radiance (RGBA32F)
// vpl_upsample.comp: full-resolution interpolation of the low-resolution indirect light.
#define VPL_UPSAMPLE_BINDING_POSITION 0         // G-buffer world position
#define VPL_UPSAMPLE_BINDING_NORMAL 1           // G-buffer normal
#define VPL_UPSAMPLE_BINDING_LOW_RES_INDIRECT 2 // indirect radiance at the gather resolution
#define VPL_UPSAMPLE_BINDING_INDIRECT 3         // output: full-resolution indirect radiance (RGBA32F)
#define VPL_UPSAMPLE_BINDING_REFINE_LIST 4      // refine list (gi/vpl_refine_list.h), appended to
// vpl_refine.comp: the full gather at the pixels of the refine list.
#define VPL_REFINE_BINDING_POSITION 0      // G-buffer world position
#define VPL_REFINE_BINDING_NORMAL 1        // G-buffer normal
#define VPL_REFINE_BINDING_ALBEDO 2        // G-buffer albedo
#define VPL_REFINE_BINDING_VPLS 3          // VplRecord per positive VPL
#define VPL_REFINE_BINDING_NEGATIVE_VPLS 4 // VplRecord per negative VPL (the positive ones when off: count 0)
#define VPL_REFINE_BINDING_REFINE_LIST 5   // refine list (gi/vpl_refine_list.h), also the dispatch's command
#define VPL_REFINE_BINDING_INDIRECT 6      // output: the upsampled indirect radiance, refined pixels rewritten
#define VPL_REFINE_BINDING_OCCUPANCY 7     // vpl_refine_visible.comp only: the voxel grid's albedo volume
#define VPL_REFINE_BINDING_VISIBILITY_MAP 8 // vpl_refine_maps.comp only: the VPLs' visibility maps
// vpl_bounce.comp: one more diffuse bounce, each VPL of generation g - 1 tracing one ray through
// the voxel grid to where a VPL of generation g sits (instant radiosity, Keller 1997).
#define VPL_BOUNCE_BINDING_DIRECTIONS 0 // the generation table: xyz local cosine-lobe direction, w source index
#define VPL_BOUNCE_BINDING_ALBEDO 1     // the voxel grid's albedo volume (rgb albedo, a = occupancy, gi/voxel_grid.h)
#define VPL_BOUNCE_BINDING_FACES 2      // the voxel grid's faces volume (R32UI, voxelFacesPack)
#define VPL_BOUNCE_BINDING_VPLS 3       // VplRecord buffer: reads generation g - 1, writes generation g
#define VPL_BOUNCE_BINDING_HALVES 4     // half voxels (grid.y twice the volumes' size): the normal volume, a = the bits
// vpl_visibility_map.comp (vpl.visibility maps): per VPL, the distance its light travels through the
// voxel grid in each texel of a hemi-octahedral map about its normal (gi/vpl_visibility.h).
#define VPL_VISIBILITY_MAP_BINDING_VPLS 0   // VplRecord per positive VPL (every generation written)
#define VPL_VISIBILITY_MAP_BINDING_ALBEDO 1 // the voxel grid's albedo volume (a = occupancy)
#define VPL_VISIBILITY_MAP_BINDING_HALVES 2 // with half voxels: the normal volume, a = half-voxel bits
#define VPL_VISIBILITY_MAP_BINDING_MAP 3    // output: float per VPL and texel, VPL-major (metres)
// vpl_importance.comp: a large sun window's candidate VPLs weighted by the light they bring to a
// sparse set of the frame's visible points (docs/vpl.md, "Candidates weighted by the image").
#define VPL_IMPORTANCE_BINDING_POSITION 0   // G-buffer world position (w = 1 where geometry)
#define VPL_IMPORTANCE_BINDING_NORMAL 1     // G-buffer normal
#define VPL_IMPORTANCE_BINDING_ALBEDO 2     // G-buffer albedo
#define VPL_IMPORTANCE_BINDING_CANDIDATES 3 // VplRecord per candidate (vpl_generate.comp over the candidate table)
#define VPL_IMPORTANCE_BINDING_WEIGHTS 4    // output: float per candidate, its estimated contribution
#define VPL_IMPORTANCE_BINDING_OCCUPANCY 5  // vpl_importance_visible.comp only: the grid's occupancy (as the gather's)
// vpl_select.comp: per focused sun, N of its candidates by priority sampling into its VPL slots.
#define VPL_SELECT_BINDING_TABLE 0      // the candidate table: xy window NDC, z area (m^2), w light index
#define VPL_SELECT_BINDING_IDS 1        // uint per candidate: its world-fixed id (lattice point)
#define VPL_SELECT_BINDING_CANDIDATES 2 // VplRecord per candidate
#define VPL_SELECT_BINDING_WEIGHTS 3    // float per candidate (vpl_importance.comp)
#define VPL_SELECT_BINDING_VPLS 4       // output: the sun's slots of the VplRecord buffer
#define VPL_SELECT_BINDING_DIRECTIONS 5 // output: the bounce rays of the selected VPLs' children (the generation table)
// Halton pixels (bases 2, 3) of the G-buffer at which each candidate's light is estimated.
#define GI_VPL_IMPORTANCE_PIXELS 64u
// Work-group width of vpl_select.comp: one group per focused sun.
#define GI_VPL_SELECT_LOCAL_SIZE 256

// Texels per side of a VPL's visibility map: side^2 rays per VPL.
#define GI_VPL_VISIBILITY_MAP_SIDE 12u

// Refine list (layout in gi/vpl_refine_list.h): a uint count and the refine pass's indirect
// dispatch command, then one packed pixel (x | y << 16) per entry.
#define VPL_REFINE_LIST_HEADER_BYTES 16

GI_NAMESPACE_BEGIN

// One positive VPL (a surface point seen by the light) or one negative VPL (a camera-visible
// point that passes the indirect light it receives on, with negative sign).
GI_GPU_STRUCT(VplRecord) {
    vec4 position;  // xyz world position, w = 1 valid / 0 empty (the sample hit nothing)
    vec4 direction; // xyz: surface normal (positive VPL) or lobe axis = mean travel direction (negative)
    vec4 flux;      // rgb flux in cd*sr; w = r^2, the squared radius of the disc of surface the VPL
                    // stands for (its share of the area the RSM or the G-buffer sampled, / pi):
                    // the length scale of the gathers' 1/d^2 clamp
};
GI_CHECK_SIZE(VplRecord, 48);

// Per-light parameters of the generation pass, one table entry per light. The RSM layer
// projections come from the shadow views table (GpuShadowView, gi/direct_types.h). A
// directional light (orthographic layer) uses only position.w (1/N) and info.
GI_GPU_STRUCT(VplLight) {
    vec4 position; // xyz light position, w = solid angle each VPL stands for (cone solid angle / N),
                   // or for a directional light the share of the RSM window (1 / N)
    vec4 axisX;    // spot frame: world-space images of the local x, y, z axes (z = spot axis)
    vec4 axisY;
    vec4 axisZ;
    uvec4 info;    // x 0 (each sample direction names its light), y VPL count,
                   // z first RSM layer, w RSM layer count (1 = one perspective layer, 6 = cube)
};
GI_CHECK_SIZE(VplLight, 80);
GI_CHECK_OFFSET(VplLight, info, 64);

// Push constants of the 1D passes (VPL and negative-VPL generation).
GI_GPU_STRUCT(VplGeneratePush) {
    uvec4 info;   // x light count (generation) / negative VPL count, y total records, z low-res factor, w 0
    uvec4 size;   // x, y low-res size; z, w full-res size (negative generation)
    vec4 camera;  // xyz camera position, w tan(half vertical field of view)
};
GI_CHECK_SIZE(VplGeneratePush, 48);

// Push constants of vpl_emitter.comp.
GI_GPU_STRUCT(VplEmitterPush) {
    uvec4 info;    // x the emitter's source index, y total records, z 1 when no light's pass wrote the
                   // buffer before (this pass then also empties the other sources' slots), w 0
    uvec4 surfels; // x emissive surfels M, y the surfel images' side R (surfel k at texel (k mod R, k / R)), z, w 0
    vec4 scale;    // x M / N: the surfels one emitter VPL stands for, y, z, w 0
};
GI_CHECK_SIZE(VplEmitterPush, 48);

// Push constants of the per-pixel passes (gather, interleave filter, negative gather, upsample,
// refine).
GI_GPU_STRUCT(VplPixelPush) {
    uvec4 size;       // x width, y height of the image being written, z low-res factor, w refine capacity
    uvec4 counts;     // x positive VPLs, y negative VPLs, z full-res width, w full-res height
    vec4 camera;      // xyz camera position, w 0
    vec4 params;      // x clamp^2 (VplSettings::clampDistance: the 1/d^2 clamp radius in units of each
                      // VPL's footprint radius, flux.w), y refine threshold, z interleave filter's plane tolerance
                      // (fraction of the distance to the camera), w 1 when the filter passes must
                      // also filter the travel directions (negative VPLs read them), else 0
    uvec4 interleave; // x tile side n (1 = every pixel gathers every VPL), y sources of the subset
                      // layout (lights x VPL generations), z VPLs per source, w voxels per axis of
                      // the visibility grid (0 without visibility)
    vec4 grid;        // visibility: xyz the voxel grid's min corner (world), w voxel edge (m)
};
GI_CHECK_SIZE(VplPixelPush, 96);

// Push constants of vpl_bounce.comp and vpl_visibility_map.comp (info.z, w unused there).
GI_GPU_STRUCT(VplBouncePush) {
    uvec4 info;  // x total records, y lights, z the generation written (1 = first bounced one), w interleave n
    uvec4 grid;  // x VPLs per light and generation (N), y voxels per axis (half voxels: twice the volumes'),
                 // z sources (lights x generations), w 0
    vec4 origin; // xyz the voxel grid's min corner (world), w voxel edge (m; half voxels: half the volumes')
};
GI_CHECK_SIZE(VplBouncePush, 48);

// Push constants of vpl_importance.comp. `interleave` and `grid` have the names and meaning of
// VplPixelPush's, which the visibility march (gi/vpl_visibility.h) reads.
GI_GPU_STRUCT(VplImportancePush) {
    uvec4 info;       // x candidates, y G-buffer pixels sampled, z, w G-buffer width and height
    vec4 params;      // x clamp^2 (as VplPixelPush::params.x), y, z, w 0
    uvec4 interleave; // x, y, z 0, w voxels per axis of the visibility grid (0 without visibility)
    vec4 grid;        // visibility: xyz the voxel grid's min corner (world), w voxel edge (m)
};
GI_CHECK_SIZE(VplImportancePush, 64);

// Push constants of vpl_select.comp.
GI_GPU_STRUCT(VplSelectPush) {
    uvec4 info;   // x candidates per focused sun M, y VPLs per source N, z interleave n, w generation-0 sources L
    uvec4 shape;  // x sources (L x generations), y generations B, z, w 0
    vec4 params;  // x the share of the weights spread by flux alone (defensive floor), y, z, w 0
};
GI_CHECK_SIZE(VplSelectPush, 48);

// Interleaved sampling (Keller & Heidrich; Segovia et al.): pixel (x, y) of the gather image
// gathers subset s = (y mod n) n + (x mod n) of the n^2 subsets. The VPL buffer is laid out
// subset-major: subset s holds, light after light, the contiguous block
// [floor(s N / n^2), floor((s + 1) N / n^2)) of each light's N Halton samples, so every subset
// is a shorter Halton run, spread over the whole cone like the full set. First record of
// subset s (s = n^2 gives the total).
GI_INLINE uint vplSubsetStart(uint s, uint n, uint lights, uint perLight) {
    return lights * ((s * perLight) / (n * n));
}

// Multi-bounce VPLs (VplSettings::bounces = B): generation g of light l (g = 0 the VPLs the RSM
// gives, g >= 1 those one more bounce away) is "source" g L + l of the subset layout above, with
// L lights and L B sources of N records each. A scene with emission counts its emitters as one
// more light, after the punctual ones (l = L - 1: the emitter VPLs and their bounced children). Each subset then holds the same Halton run of every
// source, so a subset still estimates the full sum, bounce by bounce. Record i's parent (the VPL
// of generation g - 1 whose ray placed it) is the record of the same subset and Halton index one
// generation back, `lights` blocks earlier; this returns it, or ~0u for generation 0.
GI_INLINE uint vplParentRecord(uint i, uint n, uint lights, uint sources, uint perSource) {
    uint s = 0u;
    while (s + 1u < n * n && vplSubsetStart(s + 1u, n, sources, perSource) <= i)
        s += 1u;
    uint first = vplSubsetStart(s, n, sources, perSource);
    uint block = (vplSubsetStart(s + 1u, n, sources, perSource) - first) / sources; // records per source here
    if (block == 0u || (i - first) / block < lights)
        return ~0u;
    return i - lights * block;
}

// Radical inverse of `i` in `base`: the i-th element of the van der Corput sequence, the
// coordinates of the Halton sequence (bases 2 and 3 here, as in the paper).
GI_INLINE float vplRadicalInverse(uint i, uint base) {
    float invBase = 1.0f / float(base);
    float scale = invBase;
    float result = 0.0f;
    while (i > 0u) {
        result += scale * float(i % base);
        i /= base;
        scale *= invBase;
    }
    return result;
}

// Halton point `i` (bases 2, 3) mapped to the unit sphere by the area-preserving cylinder
// projection (z = 1 - 2u, phi = 2 pi v), so equal areas of the unit square give equal solid
// angles and the points stay uniformly distributed on the sphere.
GI_INLINE vec3 vplHaltonSphere(uint i) {
    float z = 1.0f - 2.0f * vplRadicalInverse(i, 2u);
    float phi = 2.0f * GI_VPL_PI * vplRadicalInverse(i, 3u);
    float r = sqrt(max(0.0f, 1.0f - z * z));
    return vec3(r * cos(phi), r * sin(phi), z);
}

// Bounce ray `i` (Halton index, from 1) of generation `generation` >= 1: the Halton point of the
// generation's bases (5, 7; then 11, 13; then 17, 19: primes the placement does not use) mapped
// to the cosine-weighted hemisphere about +Z (Malley: uniform points of the unit disc lifted to
// the hemisphere have pdf cos / pi).
GI_INLINE vec3 vplBounceDirection(uint i, uint generation) {
    uint g = generation < 1u ? 1u : (generation > 3u ? 3u : generation);
    uint base = g == 1u ? 5u : (g == 2u ? 11u : 17u);
    float u = vplRadicalInverse(i, base);
    float v = vplRadicalInverse(i, base + 2u);
    float r = sqrt(u);
    float phi = 6.28318530718f * v;
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0f, 1.0f - u)));
}

// A uniform number in (0, 1] fixed by a world-fixed id (a candidate's lattice point): the
// candidate's priority-sampling key (vpl_select.comp). PCG's output permutation of an LCG step.
GI_INLINE float vplCandidateUniform(uint id) {
    uint state = id * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    word = (word >> 22u) ^ word;
    return (float(word >> 8u) + 1.0f) * (1.0f / 16777216.0f);
}

// Solid angle of texel (x, y) of a square-pixel perspective image of `width` x `height` whose
// vertical half-angle has tangent `tanHalfY`: (texel side at unit distance)^2 / (1 + u^2 + v^2)^1.5.
GI_INLINE float vplTexelSolidAngle(float x, float y, float width, float height, float tanHalfY) {
    float side = 2.0f * tanHalfY / height;
    float u = (x + 0.5f - 0.5f * width) * side;
    float v = (y + 0.5f - 0.5f * height) * side;
    float q = 1.0f + u * u + v * v;
    return side * side / (q * sqrt(q));
}

GI_NAMESPACE_END
#endif
