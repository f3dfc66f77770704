#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
// Once per voxelization, per touched list of the grid (the whole scene's or the static one, then
// the dynamic one): sets the occupancy bits of each listed voxel, of its 2^3 block and of its
// 4^3 block in the occupied list's bit arrays (gi/vct_passes.h). Every touched voxel is
// occupied, so nothing is read from the volumes: the cost follows the occupied voxels, not N^3.
// voxel_list_append.comp then lists the set bits in grid order.
#include "gi/vct_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = VCT_COMPACT_BINDING_TOUCHED, std430) readonly buffer Touched { uint touchedHeader[GI_VOXEL_TOUCHED_HEADER]; uint touched[]; };
layout(set = 1, binding = VCT_COMPACT_BINDING_LIST, std430) buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint entries[]; };

// Sets bit i of the array at entries[base]: the lanes that share a word send one atomic (the
// touched list runs along x, so neighbouring lanes mostly share their words).
void setBit(uint base, uint i) {
    uint word = base + (i >> 5u), bit = 1u << (i & 31u);
    for (;;) {
        uint first = subgroupBroadcastFirst(word);
        if (word == first) {
            uint bits = subgroupOr(bit);
            if (subgroupElect())
                atomicOr(entries[first], bits);
            break;
        }
    }
}

void main() {
    if (gl_GlobalInvocationID.x >= touchedHeader[3])
        return;
    uint n = pc.grid.dims.x, h = n / 2u, quarter = n / 4u;
    uvec3 c = voxelListUnpack(touched[gl_GlobalInvocationID.x]);
    uint bits = voxelListBitsOffset(n);
    setBit(bits, c.x + n * (c.y + n * c.z));
    uvec3 b = c >> 1u;
    setBit(bits + n * n * n / 32u, b.x + h * (b.y + h * b.z));
    uvec3 q = c >> 2u;
    setBit(voxelListCoarseBitsOffset(n), q.x + quarter * (q.y + quarter * q.z));
}
