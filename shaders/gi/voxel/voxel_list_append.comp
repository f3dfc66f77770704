#version 460
#extension GL_GOOGLE_include_directive : require
// Once per voxelization, after voxel_compact.comp: appends every occupied voxel and 2^3 block
// to the occupied lists (headers = indirect dispatch arguments, gi/voxel_passes.h) from their
// bits, one invocation per 32-bit word (32 neighbours along x), so consecutive list entries
// are neighbours in the grid and the SIMD lanes of the passes over the list march, gather and
// store coherently (appending in the voxelizer's touch order interleaved different triangles'
// voxels: the voxel light measured ~1.3x slower). The list order still depends on scheduling
// between words; every consumer writes per voxel, so results do not.
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = 1, std430) buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint entries[]; };

// Appends the set bits of `word` (bit i = element first + i of a grid of side `side`) to the
// list whose header quad starts at `quad` and whose slots start at entries[slots].
void append(uint word, uint first, uint side, uint quad, uint slots) {
    uint count = bitCount(word);
    uint slot = atomicAdd(header[quad + 3u], count);
    // x = ceil(count / group) over all words: each word adds the groups its slots open.
    uint groups = (slot + count + GI_VOXEL_LIST_GROUP - 1u) / GI_VOXEL_LIST_GROUP -
                  (slot + GI_VOXEL_LIST_GROUP - 1u) / GI_VOXEL_LIST_GROUP;
    if (groups > 0u)
        atomicAdd(header[quad], groups);
    while (word != 0u) {
        uint i = first + uint(findLSB(word));
        word &= word - 1u;
        entries[slots + slot++] = voxelListPack(uvec3(i % side, (i / side) % side, i / (side * side)));
    }
}

void main() {
    uint n = pc.grid.dims.x, h = n / 2u;
    uint voxelWords = n * n * n / 32u, blockWords = h * h * h / 32u;
    uint w = gl_GlobalInvocationID.x;
    if (w == 0u) {
        header[1] = header[2] = 1u; // dispatch y, z (the clear pass zeroed the header)
        header[GI_VOXEL_LIST_BLOCKS + 1u] = header[GI_VOXEL_LIST_BLOCKS + 2u] = 1u;
    }
    uint bits = voxelListBitsOffset(n);
    if (w < voxelWords) {
        uint word = entries[bits + w];
        if (word != 0u)
            append(word, 32u * w, n, 0u, 0u);
    } else if (w < voxelWords + blockWords) {
        uint word = entries[bits + w];
        if (word != 0u)
            append(word, 32u * (w - voxelWords), h, GI_VOXEL_LIST_BLOCKS, n * n * n);
    }
}
