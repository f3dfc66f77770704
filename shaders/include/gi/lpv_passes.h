// Shader interface of the LPV passes around propagation (injection from the RSM, resolve,
// lookup), shared by C++ and GLSL: grid placement, push constants, bindings, the layout of the
// injection buffer and its fixed-point scale.
//
// Stored SH volumes are normalised: every value is divided by the frame's largest RSM texel
// flux M (max over colour channels), which the range pass finds on the GPU. Lights from 1e-6 to
// 1e9 therefore store the same numbers (no float16 overflow or underflow); the lookup
// multiplies M back in.
#ifndef VKGI_GI_LPV_PASSES_H
#define VKGI_GI_LPV_PASSES_H

#include "gi/lpv.h"

// Injection buffer (int32): [0] = M as float bits (atomicMax of positive floats as uint),
// [1..3] unused, then LPV_INJECT_CELL_INTS ints per cell: (R, G, B) x 4 SH coefficients in
// fixed point (value * scale), summed with integer atomics: exact and order-independent.
#define LPV_INJECT_HEADER_INTS 4
#define LPV_INJECT_CELL_INTS 12

// Bindings (set 1) of inject_range.comp, inject.comp and inject_reduce.comp.
#define LPV_INJECT_BINDING_POSITION 0 // RSM world position (RGBA32F 2D array, w = 1 where valid)
#define LPV_INJECT_BINDING_NORMAL 1   // RSM normal (RGBA16F 2D array)
#define LPV_INJECT_BINDING_FLUX 2     // RSM reflected flux (RGBA32F 2D array)
#define LPV_INJECT_BINDING_BUFFER 3   // injection buffer (not bound by inject_reduce.comp)
#define LPV_REDUCE_BINDING_POSITION 4 // reduced RSM written by inject_reduce.comp (same formats as the RSM)
#define LPV_REDUCE_BINDING_NORMAL 5
#define LPV_REDUCE_BINDING_FLUX 6
// The full-resolution RSM behind a reduced one (inject.comp): the texels of blocks marked
// LPV_REDUCE_SPLIT are injected one by one from it. Without reduction, the RSM itself.
#define LPV_INJECT_BINDING_SOURCE_POSITION 7
#define LPV_INJECT_BINDING_SOURCE_NORMAL 8
#define LPV_INJECT_BINDING_SOURCE_FLUX 9
// inject.comp: the shadow atlas's views (GpuShadowView per layer; the RSM has the atlas's layers),
// whose eye is the light position of point and spot layers (lpvInjectsNearLight).
#define LPV_INJECT_BINDING_SHADOW_VIEWS 10
// Position w of a reduced texel whose block one surfel cannot stand for (inject_reduce.comp):
// its texels are read one by one from the full RSM.
#define LPV_REDUCE_SPLIT 2.0
// Specialization constant id of inject_reduce.comp: the reduction factor per axis (2 or 4).
#define LPV_REDUCE_SPEC_FACTOR 0

// Bindings of inject_resolve_<format>.comp.
#define LPV_RESOLVE_BINDING_BUFFER 0         // injection buffer, read only
#define LPV_RESOLVE_BINDING_WAVEFRONT_R 1    // first wavefront (R, G, B channel images), written whole
#define LPV_RESOLVE_BINDING_WAVEFRONT_G 2
#define LPV_RESOLVE_BINDING_WAVEFRONT_B 3
#define LPV_RESOLVE_BINDING_ACCUMULATION_R 4 // accumulation volume, starts as the injected light
#define LPV_RESOLVE_BINDING_ACCUMULATION_G 5
#define LPV_RESOLVE_BINDING_ACCUMULATION_B 6

// Bindings of lookup.comp.
#define LPV_LOOKUP_BINDING_POSITION 0       // G-buffer world position (RGBA32F, w = 1 where geometry)
#define LPV_LOOKUP_BINDING_NORMAL 1         // G-buffer normal (RGBA16F)
#define LPV_LOOKUP_BINDING_ALBEDO 2         // G-buffer albedo (RGBA16F)
#define LPV_LOOKUP_BINDING_ACCUMULATION_R 3 // accumulated SH, sampled trilinearly (R, G, B channel images)
#define LPV_LOOKUP_BINDING_ACCUMULATION_G 4
#define LPV_LOOKUP_BINDING_ACCUMULATION_B 5
#define LPV_LOOKUP_BINDING_BUFFER 6         // injection buffer (for M)
#define LPV_LOOKUP_BINDING_OUTPUT 7         // indirect radiance (RGBA32F)
#define LPV_LOOKUP_BINDING_SUM 8            // channel sum R + G + B of the accumulated SH (the damping's input)

// Bindings of lookup_sum_<format>.comp.
#define LPV_SUM_BINDING_ACCUMULATION_R 0 // accumulated SH (R, G, B channel images), storage images
#define LPV_SUM_BINDING_ACCUMULATION_G 1
#define LPV_SUM_BINDING_ACCUMULATION_B 2
#define LPV_SUM_BINDING_OUTPUT 3         // their channel sum, same format

// Bindings of the geometry volume passes, gv_inject_<source>.comp and gv_resolve.comp.
#define LPV_GEOMETRY_VOLUME_BINDING_POSITION 0 // surfel positions (RSM: 2D array; camera: 2D), w = 1 where valid
#define LPV_GEOMETRY_VOLUME_BINDING_NORMAL 1   // surfel normals
#define LPV_GEOMETRY_VOLUME_BINDING_SUMS 2     // fixed-point sums: header, then 2 slots (RSM, camera) of (N+1)^3 x 4 ints
#define LPV_GEOMETRY_VOLUME_BINDING_OUTPUT 3   // geometry volume (RGBA16F, (N+1)^3)
#define LPV_GEOMETRY_VOLUME_BINDING_SOURCE_POSITION 4 // gv_inject_rsm.comp: the full RSM behind a reduced one
#define LPV_GEOMETRY_VOLUME_BINDING_SOURCE_NORMAL 5
// Fixed-point scale of the geometry volume sums: a surfel adds at most 1.0233 per coefficient
// (full coverage), so 2^16 keeps 1.5e-5 resolution and room for 32768 full-coverage surfels per cell.
#define LPV_GEOMETRY_VOLUME_FIXED_SCALE 65536.0

// Texels of one RSM row each inject invocation walks, merging runs that land in the same cell
// before its atomics: neighbouring texels nearly always share a cell, so this divides the
// atomics (the injection's bottleneck on lavapipe) by about this factor.
#define LPV_INJECT_RUN 8

GI_NAMESPACE_BEGIN

// Where an LPV sits in the world.
GI_GPU_STRUCT(LpvGrid) {
    vec4 origin; // xyz: world position of the min corner of cell (0, 0, 0); w: cell size (world units)
    ivec4 size;  // xyz: cells per axis; w: zero
};
GI_CHECK_SIZE(LpvGrid, 32);

GI_GPU_STRUCT(LpvInjectPush) {
    LpvGrid grid;
    ivec4 rsm;    // x: texels per row, y: layers, z: GV source slot (0 RSM, 1 camera), w: rows
                  // (inject.comp: z = reduction factor F >= 1, w = the full RSM's texels per row)
    vec4 params;  // x: fixed-point scale (ints per unit of normalised SH or of blocking potential);
                  // y: inject_reduce.comp's merge radius (world units), inject.comp's near-light
                  // radius (world units, lpvInjectsNearLight), the GV's camera stride;
                  // z, w: gv_inject_rsm.comp's reduction factor F and the full RSM's texels per row
};
GI_CHECK_SIZE(LpvInjectPush, 64);

GI_GPU_STRUCT(LpvLookupPush) {
    LpvGrid grid;
    ivec4 image;     // xy: output size; z: number of finer cascades in `finer` (0..2)
    vec4 params;     // x: damping strength (0 = off); y: 1 = fade at this grid's border; z: 1 = add to the output
    LpvGrid finer[2]; // finer cascades whose interior this one yields to
};
GI_CHECK_SIZE(LpvLookupPush, 128);

// Cascade border fade at world position p: 1 more than 3 cells inside the grid, 0 in its
// outermost cell, linear in between (blending width 2 cells).
GI_INLINE float lpvBorderFade(LpvGrid grid, vec3 p) {
    vec3 g = (p - vec3(grid.origin)) / grid.origin.w;
    vec3 d = min(g, vec3(grid.size) - g);
    return clamp((min(d.x, min(d.y, d.z)) - 1.0f) * 0.5f, 0.0f, 1.0f);
}

// Cell a surfel at world position `p` with unit normal `n` is injected into: the cell containing
// p moved half a cell along n (so a wall's light starts in front of it, not inside it).
GI_INLINE ivec3 lpvInjectionCell(LpvGrid grid, vec3 p, vec3 n) {
    vec3 g = (p - vec3(grid.origin)) / grid.origin.w + 0.5f * n;
    return ivec3(floor(g));
}

// Continuous grid coordinate of world position p, in cells, with cell centres at integers
// (the coordinate trilinear interpolation between cell centres uses).
GI_INLINE vec3 lpvGridCoordinate(LpvGrid grid, vec3 p) {
    return (p - vec3(grid.origin)) / grid.origin.w - 0.5f;
}

// Whether a surfel at world position p of an RSM layer whose view has eye `eye` (GpuShadowView)
// is injected: not when it lies closer than `radius` (the finest grid's cell) to a point or spot
// light (eye.w > 0: perspective; directional layers inject everything). Such a surfel reflects
// the light from, in effect, the light's own position: a source smaller than a cell, which the
// volume carries only as beams along the grid axes (the ray effect) and as grazing light over
// its own surface. A point light 1 cm under a plane sends 1 - h / r = 74% of its upward light
// onto the plane within r = 3.9 cm of it (the Cornell box's cell): docs/lpv.md, "Surfels next to
// a light".
GI_INLINE bool lpvInjectsNearLight(vec4 eye, vec3 p, float radius) {
    vec3 d = p - vec3(eye);
    return !(eye.w > 0.0f) || dot(d, d) >= radius * radius;
}

// Fixed-point scale for an injection of `texels` RSM texels: one texel's normalised SH is at
// most 1/pi * 1.0233 = 0.3258 per coefficient, so even all texels in one cell stay below 2^31.
GI_INLINE float lpvFixedPointScale(float texels) {
    return 2.0e9f / (0.3258f * max(texels, 1.0f));
}

GI_NAMESPACE_END

#endif
