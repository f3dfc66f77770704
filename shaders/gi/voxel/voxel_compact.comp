#version 460
#extension GL_GOOGLE_include_directive : require
// Once per voxelization, per touched list of the grid (the whole scene's or the static one, then
// the dynamic one): appends each listed voxel not yet in the occupied list, and its 2^3 block if
// that is not listed yet, to the occupied lists (headers = indirect dispatch arguments,
// gi/voxel_passes.h); the "listed" bits after the block slots decide. Every touched voxel is
// occupied, so nothing is read from the volumes: the cost follows the occupied voxels, not N^3.
// Level 0 of the directional volume is cleared by a transfer before, so the passes that then
// run over the list alone leave a complete level 0 behind.
// The list order depends on scheduling; its consumers write per voxel, so results do not.
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = 0, std430) readonly buffer Touched { uint touchedHeader[GI_VOXEL_TOUCHED_HEADER]; uint touched[]; };
layout(set = 1, binding = 1, std430) buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint entries[]; };

// Sets bit `i` of the bit array at entries[base]; true if this call set it.
bool claim(uint base, uint i) {
    uint bit = 1u << (i & 31u);
    return (atomicOr(entries[base + (i >> 5u)], bit) & bit) == 0u;
}

void main() {
    uint n = pc.grid.dims.x;
    uint h = n / 2u;
    if (gl_GlobalInvocationID.x == 0u) {
        header[1] = header[2] = 1u; // dispatch y, z (the clear pass zeroed the header)
        header[GI_VOXEL_LIST_BLOCKS + 1u] = header[GI_VOXEL_LIST_BLOCKS + 2u] = 1u;
    }
    if (gl_GlobalInvocationID.x >= touchedHeader[3])
        return;
    uint packed = touched[gl_GlobalInvocationID.x];
    uvec3 c = voxelListUnpack(packed);
    uint voxelBits = voxelListBitsOffset(n);
    if (!claim(voxelBits, c.x + n * (c.y + n * c.z)))
        return; // a dynamic voxel inside a static one: listed with the static list
    uvec3 q = c >> 2u;
    uint quarter = n / 4u;
    uint coarse = q.x + quarter * (q.y + quarter * q.z);
    atomicOr(entries[voxelListCoarseBitsOffset(n) + (coarse >> 5u)], 1u << (coarse & 31u));
    uint slot = atomicAdd(header[3], 1u);
    entries[slot] = packed;
    // The first voxel of each group of GI_VOXEL_LIST_GROUP adds that group: x = ceil(count / group).
    if (slot % GI_VOXEL_LIST_GROUP == 0u)
        atomicAdd(header[0], 1u);
    uvec3 b = c >> 1u;
    if (claim(voxelBits + n * n * n / 32u, b.x + h * (b.y + h * b.z))) {
        uint blockSlot = atomicAdd(header[GI_VOXEL_LIST_BLOCKS + 3u], 1u);
        entries[n * n * n + blockSlot] = voxelListPack(b);
        if (blockSlot % GI_VOXEL_LIST_GROUP == 0u)
            atomicAdd(header[GI_VOXEL_LIST_BLOCKS], 1u);
    }
}
