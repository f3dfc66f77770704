#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
// After a voxelization: lists the voxels whose touched bits voxelize.comp set (bit x + N (y + N z)
// of a word array, one bit per voxel) in the touched list (gi/voxel_passes.h), one invocation per
// 32-bit word, and zeroes the words, so the bits are zero for the next voxelization. Grid order
// within each subgroup's 8 x 32 voxels: the resolve and the stale clear that run over the list
// then store to neighbouring texels (appended in the voxelizer's order their scattered image
// stores missed the cache).
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = VOXEL_TOUCHED_BINDING_BITS, std430) buffer Bits { uint bits[]; };
layout(set = 1, binding = VOXEL_TOUCHED_BINDING_LIST, std430) buffer Touched { uint touchedHeader[GI_VOXEL_TOUCHED_HEADER]; uint touched[]; };

void main() {
    uint n = pc.grid.dims.x, shift = pc.grid.dims.y;
    uint w = gl_GlobalInvocationID.x;
    uint word = 0u;
    if (w < (n * n * n) / 32u) {
        word = bits[w];
        if (word != 0u)
            bits[w] = 0u;
    }
    uint count = bitCount(word);
    uint total = subgroupAdd(count);
    uint slot = subgroupExclusiveAdd(count);
    uint base = 0u;
    if (subgroupElect() && total > 0u) {
        base = atomicAdd(touchedHeader[3], total);
        // Dispatch x = ceil(count / group): the groups that slots [base, base + total) open.
        uint groups = (base + total + GI_VOXEL_LIST_GROUP - 1u) / GI_VOXEL_LIST_GROUP -
                      (base + GI_VOXEL_LIST_GROUP - 1u) / GI_VOXEL_LIST_GROUP;
        if (groups > 0u)
            atomicAdd(touchedHeader[0], groups);
    }
    slot += subgroupBroadcastFirst(base);
    while (word != 0u) {
        uint i = 32u * w + uint(findLSB(word));
        word &= word - 1u;
        touched[slot++] = voxelListPack(uvec3(i & (n - 1u), (i >> shift) & (n - 1u), i >> (2u * shift)));
    }
}
