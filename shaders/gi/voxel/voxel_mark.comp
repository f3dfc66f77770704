#version 460
#extension GL_GOOGLE_include_directive : require
// After a moved clipmap level's volumes were shifted to its new corner: sets the touched bit of
// every occupied voxel, one invocation per 32-bit word of bits (plain stores: the bits are zero
// and the slab voxelization that ORs its own bits in runs after). The touched list then covers
// the kept voxels too, as the stale clear and the VCT list expect of a voxelization's list.
#include "gi/voxel_passes.h"

layout(local_size_x = 64) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = VOXEL_MARK_BINDING_ALBEDO, rgba8) uniform readonly image3D albedo;
layout(set = 1, binding = VOXEL_MARK_BINDING_BITS, std430) buffer Bits { uint bits[]; };

void main() {
    uint n = pc.grid.dims.x, shift = pc.grid.dims.y;
    uint w = gl_GlobalInvocationID.x;
    if (w >= (n * n * n) / 32u)
        return;
    uint word = 0u;
    for (uint b = 0u; b < 32u; ++b) {
        uint i = 32u * w + b;
        ivec3 c = ivec3(i & (n - 1u), (i >> shift) & (n - 1u), i >> (2u * shift));
        if (imageLoad(albedo, c).a > 0.0)
            word |= 1u << b;
    }
    bits[w] = word;
}
