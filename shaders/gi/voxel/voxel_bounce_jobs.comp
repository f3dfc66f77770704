#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce, job list: per block (bounceBlockSide^3 voxels), the classes of its voxels'
// normals (voxel_block.glsl; each 4^3 block's own invocation, OR-ed in shared memory) -> the
// block's class mask and one job per class, appended to that class's list, and the gathers'
// indirect dispatch (gi/voxel_passes.h); zeroes the misfit bits. The order within a class's list follows the
// scheduling; each gather depends only on its block and class and stores its result at them,
// so the images do not.
#include "gi/voxel_passes.h"

// One invocation per 4^3 block of the grid; the 4^3 blocks of a bounce block are consecutive
// invocations of one work group ((N/4)^3 is a multiple of the group size from N = 16 on).
layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = 0, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = 1, std430) readonly buffer List { uint listHeader[GI_VOXEL_LIST_HEADER]; uint entries[]; };
layout(set = 1, binding = 2, std430) buffer Jobs { uint header[GI_BOUNCE_HEADER]; uint words[]; };
#define VOXEL_BLOCK_LIST
#include "voxel_block.glsl"

shared uint classMasks[GI_VOXEL_LIST_GROUP]; // per bounce block of the group

void main() {
    uint n = pc.grid.dims.x, side = n / bounceBlockSide(n);
    int sub = int(bounceBlockSide(n) / 4u);
    uint subCount = uint(sub * sub * sub);
    uint i4 = gl_GlobalInvocationID.x, b = i4 / subCount, s = i4 % subCount;
    uint local = gl_LocalInvocationIndex / subCount;
    if (i4 == 0u) { // dispatch y, z of both quads (the clear zeroed the header)
        header[1] = GI_BOUNCE_CLASSES;
        header[2] = header[GI_BOUNCE_MISFITS + 1u] = header[GI_BOUNCE_MISFITS + 2u] = 1u;
    }
    if (s == 0u)
        classMasks[local] = 0u;
    barrier();
    // The occupied voxels only, through the list's bits (an empty block's mask is 0: the apply
    // reads the masks of neighbouring blocks).
    ivec3 q4 = bounceSubBlock(ivec3(b % side, (b / side) % side, b / (side * side)), int(s), sub);
    uint misfitWord = bounceMisfitBitsOffset(n) + bounceMisfitBit(uvec3(4 * q4), n).x;
    words[misfitWord] = words[misfitWord + 1u] = 0u; // the gathers set them
    uint mask = 0u;
    if (coarseOccupied(q4, n)) {
        for (int row = 0; row < 16; ++row) {
            ivec3 r = 4 * q4 + ivec3(0, row & 3, row >> 2);
            for (uint bits = rowOccupancy(r, n); bits != 0u; bits &= bits - 1u) {
                vec3 normal;
                uint k;
                if (voxelNormalOf(r + ivec3(findLSB(bits), 0, 0), normal, k))
                    mask |= 1u << k;
            }
        }
    }
    if (mask != 0u)
        atomicOr(classMasks[local], mask);
    barrier();
    if (s != 0u)
        return;
    mask = classMasks[local];
    words[b] = mask;
    while (mask != 0u) {
        uint k = uint(findLSB(mask));
        mask &= mask - 1u;
        uint slot = atomicAdd(header[GI_BOUNCE_COUNTS + k], 1u);
        if (slot % GI_VOXEL_LIST_GROUP == 0u) // x = ceil(largest count / group)
            atomicMax(header[0], slot / GI_VOXEL_LIST_GROUP + 1u);
        words[bounceJobOffset(n) + k * bounceBlockCount(n) + slot] = b;
    }
}
