#version 460
#extension GL_GOOGLE_include_directive : require
// Once per voxelization, after voxel_list_append.comp: zeroes what levels 0 and 1 of the
// directional volume hold from the last voxelization at voxels and 2^3 blocks that are empty now
// (gi/vct_passes.h, "written"): the voxel light stores only the listed voxels' views, the
// level-1 mip only the listed blocks. One invocation per word of the list's bits, as the append
// (32 voxels along x, or 32 blocks), against the same word of the last list; the voxels still
// occupied are the voxel light's (it zeroes the views its voxel's new faces no longer cover).
// Re-voxelizing unchanged geometry zeroes nothing: one compare per word.
#include "gi/vct_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = VCT_STALE_BINDING_LIST, std430) readonly buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint entries[]; };
layout(set = 1, binding = VCT_STALE_BINDING_WRITTEN_BITS, std430) buffer WrittenBits { uint writtenBits[]; };
layout(set = 1, binding = VCT_STALE_BINDING_WRITTEN, r8ui) uniform uimage3D written;
layout(set = 1, binding = VCT_STALE_BINDING_LEVEL0, rgba16f) uniform writeonly image2DArray level0;
layout(set = 1, binding = VCT_STALE_BINDING_LEVEL1, rgba16f) uniform writeonly image2DArray level1;

void main() {
    uint n = pc.grid.dims.x, h = n / 2u;
    uint voxelWords = n * n * n / 32u;
    uint w = gl_GlobalInvocationID.x;
    if (w >= voxelWrittenBitsWords(n))
        return;
    uint now = entries[voxelListBitsOffset(n) + w], before = writtenBits[w];
    if (before == now)
        return;
    writtenBits[w] = now;
    uint stale = before & ~now;
    bool isVoxel = w < voxelWords;
    uint shift = isVoxel ? pc.grid.dims.y : pc.grid.dims.y - 1u, mask = (1u << shift) - 1u;
    uint first = 32u * (isVoxel ? w : w - voxelWords);
    while (stale != 0u) {
        uint i = first + uint(findLSB(stale));
        stale &= stale - 1u;
        ivec3 c = ivec3(i & mask, (i >> shift) & mask, i >> (2u * shift));
        if (!isVoxel) { // a block: its six level-1 views
            for (uint d = 0u; d < GI_VCT_DIRECTIONS; ++d)
                imageStore(level1, vctDirectionalTexel(c, d, n), vec4(0.0));
            continue;
        }
        uint axes = imageLoad(written, c).x;
        imageStore(written, c, uvec4(0u));
        for (uint a = 0u; a < 3u; ++a)
            if ((axes & (1u << a)) != 0u) {
                imageStore(level0, vctDirectionalTexel(c, 2u * a, n), vec4(0.0));
                imageStore(level0, vctDirectionalTexel(c, 2u * a + 1u, n), vec4(0.0));
            }
    }
}
