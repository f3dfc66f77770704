#version 460
#extension GL_GOOGLE_include_directive : require
// A moved clipmap level's kept voxels: for each voxel of the last voxelization's touched list
// (indirect dispatch over it; it holds every nonzero voxel the volumes had), sets the touched bit
// of its index after the move if the level still covers it. The touched list built from the bits
// then covers the volumes after the shift and the slab voxelization, as the stale clear and the
// VCT list expect; the resolve skips these voxels (no record). Work in proportion to the occupied
// voxels, and no image reads.
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelMarkPush pc; };
layout(set = 1, binding = VOXEL_MARK_BINDING_PREVIOUS, std430) readonly buffer Touched { uint touchedHeader[GI_VOXEL_TOUCHED_HEADER]; uint touched[]; };
layout(set = 1, binding = VOXEL_MARK_BINDING_BITS, std430) buffer Bits { uint bits[]; };

void main() {
    if (gl_GlobalInvocationID.x >= touchedHeader[3])
        return;
    int n = int(pc.grid.dims.x);
    ivec3 c = ivec3(voxelListUnpack(touched[gl_GlobalInvocationID.x])) - pc.move.xyz;
    if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, ivec3(n))))
        return; // left the level
    uint i = uint(c.x + n * (c.y + n * c.z));
    atomicOr(bits[i >> 5u], 1u << (i & 31u));
}
