#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
// Once per voxelization, after voxel_compact.comp: appends every occupied voxel and 2^3 block
// to the occupied lists (headers = indirect dispatch arguments, gi/vct_passes.h) from their
// bits, one invocation per 32-bit word (32 neighbours along x), so consecutive list entries
// are neighbours in the grid and the SIMD lanes of the passes over the list march, gather and
// store coherently (appending in the voxelizer's touch order interleaved different triangles'
// voxels, and the voxel light ran slower). One atomic per subgroup and list reserves the
// slots of the subgroup's words. The list order still depends on scheduling between
// subgroups; every consumer writes per voxel, so results do not.
#include "gi/vct_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = VCT_APPEND_BINDING_LIST, std430) buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint entries[]; };

// Reserves `count` slots per lane in the list whose header quad starts at `quad` (one atomic
// per subgroup, adding the dispatch groups the slots open); returns the lane's first slot.
uint reserve(uint count, uint quad) {
    uint total = subgroupAdd(count);
    uint before = subgroupExclusiveAdd(count);
    uint base = 0u;
    if (subgroupElect() && total > 0u) {
        base = atomicAdd(header[quad + 3u], total);
        // x = ceil(count / group) over all subgroups: each adds the groups its slots open.
        uint groups = (base + total + GI_VOXEL_LIST_GROUP - 1u) / GI_VOXEL_LIST_GROUP -
                      (base + GI_VOXEL_LIST_GROUP - 1u) / GI_VOXEL_LIST_GROUP;
        if (groups > 0u)
            atomicAdd(header[quad], groups);
    }
    return subgroupBroadcastFirst(base) + before;
}

void main() {
    uint n = pc.grid.dims.x, h = n / 2u;
    uint voxelWords = n * n * n / 32u, blockWords = h * h * h / 32u;
    uint w = gl_GlobalInvocationID.x;
    if (w == 0u) {
        header[1] = header[2] = 1u; // dispatch y, z (the clear pass zeroed the header)
        header[GI_VOXEL_LIST_BLOCKS + 1u] = header[GI_VOXEL_LIST_BLOCKS + 2u] = 1u;
    }
    bool isVoxel = w < voxelWords, isBlock = !isVoxel && w < voxelWords + blockWords;
    uint word = isVoxel || isBlock ? entries[voxelListBitsOffset(n) + w] : 0u;
    uint count = bitCount(word);
    uint voxelSlot = reserve(isVoxel ? count : 0u, 0u);
    uint blockSlot = reserve(isBlock ? count : 0u, GI_VOXEL_LIST_BLOCKS);
    // Voxels: slots from 0, grid of side n; blocks: slots after the N^3 voxel slots, side n / 2.
    uint slot = isVoxel ? voxelSlot : n * n * n + blockSlot;
    uint shift = isVoxel ? pc.grid.dims.y : pc.grid.dims.y - 1u, mask = (1u << shift) - 1u;
    uint first = 32u * (isVoxel ? w : w - voxelWords);
    while (word != 0u) {
        uint i = first + uint(findLSB(word));
        word &= word - 1u;
        entries[slot++] = voxelListPack(uvec3(i & mask, (i >> shift) & mask, i >> (2u * shift)));
    }
}
