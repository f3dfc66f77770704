// The shared voxel grid (C++ and GLSL): a dense N^3 grid of cubic voxels that the VCT passes
// write and other techniques (LPV multi-bounce) read. One header defines the parameters, the
// fixed-point accumulation format and the encoding of the resolved volumes.
//
// Resolved volumes (3D images, N^3, texel (x,y,z) = voxel whose world-space min corner is
// origin + voxelSize * (x,y,z)):
//   albedo   RGBA8_UNORM   rgb = mean linear albedo of the triangles touching the voxel,
//                          a = occupancy (1 = at least one triangle touches it, else 0)
//   normal   RGBA8_UNORM   rgb = voxelNormalEncode(mean face normal) (0.5 = zero vector when the
//                          normals cancel, e.g. both sides of a thin wall), a = occupancy (1), or
//                          with dims.z = 1 the voxel's half-voxel occupancy over 255: bit
//                          i + 2 j + 4 k set when a triangle touches the half-size box (i, j, k) of
//                          the voxel's 2x2x2 (i = 0 the lower half in x); nonzero exactly where
//                          the voxel is occupied (voxelHalfBits)
//   emission RGBA16F       rgb = mean emitted radiance (nits) * radianceScale; a = 0, or with
//                          dims.w = 1 the voxel's fill: the share of its cross-section its
//                          surfaces block (pre-filtered opacity, docs/vct.md "Pre-filtered
//                          opacity"), min(1, sum_k P_k s_k) with P_k the triangles' area inside
//                          the voxel projected along axis k over the voxel's face area and s_k the
//                          larger of the +k and -k face coverages over their sum (a closed surface
//                          covers its silhouette twice, once from each side)
//   faces    R32UI         which way the voxel's surfaces face: for each of the six axis
//                          directions +X, -X, +Y, -Y, +Z, -Z the mean over its triangles of
//                          max(0, +-n_axis) (the share of a triangle's area seen from that side),
//                          quantised to 5 bits each (voxelFacesPack). A roof voxel holding only
//                          the sunlit top has +Y only; one holding both faces of a thin wall has
//                          +Y and -Y. The mean normal is (+X - -X, +Y - -Y, +Z - -Z).
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
    uvec4 dims;       // x = N (power of two), y = log2(N), z = 1: record the half-voxel
                      // occupancy (normal's a; VCT's grids and the camera-centred shared grid),
                      // else 0; w = 1: record the fill (emission's a; VCT's pre-filtered
                      // opacity), else 0
};
GI_CHECK_SIZE(VoxelGridParams, 48);
GI_CHECK_OFFSET(VoxelGridParams, dims, 32);

// Stored value of the brightest radiance: 2^12 leaves 16x of half-float headroom (65504) for
// bounces adding up and keeps radiance down to 1.5e-8 of the maximum out of the subnormals
// (6.1e-5), where half floats lose relative precision.
#define GI_VOXEL_RADIANCE_TARGET 4096.0

// Fixed-point accumulation (uint words, summed with integer atomics so that the result does not
// depend on the order in which triangles arrive: two runs give bit-identical grids). Each
// contribution adds value * GI_VOXEL_FIXED_ONE, rounded; the resolve divides by count.
#define GI_VOXEL_FIXED_ONE 65536.0
// Contributions per voxel are capped so that a sum (each term <= 1) stays below 2^31:
// 32767 * 65536 < 2^31 (the resolve takes differences of face sums as int32). A voxel touched by more triangles keeps the first 32767 (only
// then does the order matter; no real mesh gets close).
#define GI_VOXEL_MAX_CONTRIBUTIONS 32767u
// Accumulation record of a voxel: GI_VOXEL_ACC_STRIDE uint words at word
// GI_VOXEL_ACC_STRIDE * (x + N (y + N z)) of one storage buffer, so that one triangle's atomics
// on a voxel and the resolve's loads of it touch one 64-byte cache line (13 separate R32UI
// volumes put each of a voxel's ten atomics on a different line). Word 0 holds the count in its
// low 24 bits (2^24 triangles in one voxel would carry into the next field) and, with
// dims.z = 1, the half-voxel bits in its high 8; with dims.w = 1 words 13..15 hold the sums of
// the triangles' areas inside the voxel projected along x, y, z (fixed point, voxel face = 1),
// else they are padding.
// Empty records are zero; the resolve zeroes each record it reads, so the buffer is zero
// between voxelizations and needs no clear after the first.
// The records are bound as GI_VOXEL_ACC_SLABS descriptor ranges of whole z-layers
// (shaders/gi/voxel/voxel_acc.glsl): every device binds at least 2^27 bytes per storage buffer
// (the spec's minimum maxStorageBufferRange, lavapipe's value), and a 256^3 grid's records are
// 2^30 bytes, so there the eight ranges hold N/8 layers each; smaller grids fit in the first
// range (the others alias it, unused).
#define GI_VOXEL_ACC_SLABS 8u
#define GI_VOXEL_ACC_COUNT 0     // low GI_VOXEL_ACC_COUNT_BITS bits; the half-voxel bits above them
#define GI_VOXEL_ACC_COUNT_BITS 24u
#define GI_VOXEL_ACC_COUNT_MASK ((1u << GI_VOXEL_ACC_COUNT_BITS) - 1u)
#define GI_VOXEL_ACC_ALBEDO 1   // 3 channels: r, g, b
#define GI_VOXEL_ACC_FACES 4    // 6 channels: max(0, n.x), max(0, -n.x), max(0, n.y), ... (unsigned)
#define GI_VOXEL_ACC_EMISSION 10 // 3 channels: r, g, b (emission * radianceScale / GI_VOXEL_RADIANCE_TARGET, <= 1)
#define GI_VOXEL_ACC_AREA 13     // dims.w = 1: 3 channels: projected area inside the voxel along x, y, z
#define GI_VOXEL_ACC_CHANNELS 16u
#define GI_VOXEL_ACC_STRIDE 16u
// z-layers per descriptor range of the records of an N^3 grid.
GI_INLINE uint voxelAccSlabLayers(uint n) {
    return n * n * n * GI_VOXEL_ACC_STRIDE * 4u > (1u << 27u) ? n / GI_VOXEL_ACC_SLABS : n;
}

// Supported grid resolutions (powers of two).
#define GI_VOXEL_MIN_RESOLUTION 16u
#define GI_VOXEL_MAX_RESOLUTION 256u

// The half-voxel bits of a voxel from its normal volume's alpha (dims.z = 1): 0 for an empty voxel.
GI_INLINE uint voxelHalfBits(float normalAlpha) { return uint(normalAlpha * 255.0f + 0.5f); }

GI_INLINE vec3 voxelNormalEncode(vec3 n) { return n * 0.5f + 0.5f; }
GI_INLINE vec3 voxelNormalDecode(vec3 e) { return e * 2.0f - 1.0f; }

// Face coverages (each in [0, 1]) <-> the faces volume: 5 bits per direction, +X in the low bits.
#define GI_VOXEL_FACE_LEVELS 31.0f
GI_INLINE uint voxelFacesPack(vec3 pos, vec3 neg) {
    uint v = 0u;
    for (int k = 0; k < 3; ++k) {
        v |= uint(clamp(pos[k], 0.0f, 1.0f) * GI_VOXEL_FACE_LEVELS + 0.5f) << uint(10 * k);
        v |= uint(clamp(neg[k], 0.0f, 1.0f) * GI_VOXEL_FACE_LEVELS + 0.5f) << uint(10 * k + 5);
    }
    return v;
}
// Coverage of the faces looking towards direction d (0..5 = +X, -X, +Y, -Y, +Z, -Z).
GI_INLINE float voxelFaceCoverage(uint packed, uint d) { return float((packed >> (5u * d)) & 31u) / GI_VOXEL_FACE_LEVELS; }

GI_NAMESPACE_END
#endif
