// The shared voxel grid (C++ and GLSL): a dense N^3 grid of cubic voxels that the VCT passes
// write and other techniques (LPV multi-bounce) read. One header defines the parameters, the
// fixed-point accumulation format and the encoding of the resolved volumes.
//
// Resolved volumes (3D images, N^3, texel (x,y,z) = voxel whose world-space min corner is
// origin + voxelSize * (x,y,z)):
//   albedo   RGBA8_UNORM   rgb = mean linear albedo of the triangles touching the voxel,
//                          a = occupancy (1 = at least one triangle touches it, else 0)
//   normal   RGBA8_UNORM   rgb = voxelNormalEncode(mean face normal) (0.5 = zero vector when the
//                          normals cancel, e.g. both sides of a thin wall), a = occupancy
//   emission RGBA16F       rgb = mean emitted radiance (nits) * radianceScale, a = 0
// Empty voxels are all zero. Radiance is stored pre-multiplied by `radianceScale`, a power of
// two that maps the brightest radiance the scene can put in a voxel to about
// GI_VOXEL_RADIANCE_TARGET, so that scenes from 1e-6 to 1e9 nits use the same half-float range;
// multiply by scales.z (1 / radianceScale) to get nits back.
#ifndef VKGI_GI_VOXEL_GRID_H
#define VKGI_GI_VOXEL_GRID_H
#include "../shared/bridge.h"

GI_NAMESPACE_BEGIN

GI_GPU_STRUCT(VoxelGridParams) {
    vec4 originSize;  // xyz world-space min corner of the grid, w = voxel edge length (m)
    vec4 scales;      // x = 1 / voxel edge, y = radianceScale, z = 1 / radianceScale, w = 0
    uvec4 dims;       // x = N (power of two), y = log2(N), z = 0, w = 0
};
GI_CHECK_SIZE(VoxelGridParams, 48);
GI_CHECK_OFFSET(VoxelGridParams, dims, 32);

// Stored value of the brightest radiance: 2^12 leaves 16x of half-float headroom (65504) for
// bounces adding up and keeps radiance down to 1.5e-8 of the maximum out of the subnormals
// (6.1e-5), where half floats lose relative precision.
#define GI_VOXEL_RADIANCE_TARGET 4096.0

// Fixed-point accumulation (R32UI, summed with integer atomics so that the result does not
// depend on the order in which triangles arrive: two runs give bit-identical grids). Each
// contribution adds value * GI_VOXEL_FIXED_ONE, rounded; the resolve divides by count.
#define GI_VOXEL_FIXED_ONE 65536.0
// Contributions per voxel are capped so that a signed normal sum (|n_i| <= 1) cannot overflow
// int32: 32767 * 65536 < 2^31. A voxel touched by more triangles keeps the first 32767 (only
// then does the order matter; no real mesh gets close).
#define GI_VOXEL_MAX_CONTRIBUTIONS 32767u
// Accumulation channels, stacked along z in one R32UI image of N x N x (N * channels).
#define GI_VOXEL_ACC_COUNT 0
#define GI_VOXEL_ACC_ALBEDO 1   // 3 channels: r, g, b
#define GI_VOXEL_ACC_NORMAL 4   // 3 channels: x, y, z (two's-complement int sums)
#define GI_VOXEL_ACC_EMISSION 7 // 3 channels: r, g, b (emission * radianceScale / GI_VOXEL_RADIANCE_TARGET, <= 1)
#define GI_VOXEL_ACC_CHANNELS 10u

// Supported grid resolutions (powers of two).
#define GI_VOXEL_MIN_RESOLUTION 16u
#define GI_VOXEL_MAX_RESOLUTION 256u

GI_INLINE vec3 voxelNormalEncode(vec3 n) { return n * 0.5f + 0.5f; }
GI_INLINE vec3 voxelNormalDecode(vec3 e) { return e * 2.0f - 1.0f; }

GI_NAMESPACE_END
#endif
