#version 460
#extension GL_GOOGLE_include_directive : require
// Between the voxelization into volumes that an earlier one resolved into and the listing of
// its touched bits: zeroes the voxels of the earlier touched list (indirect dispatch over it;
// gi/voxel_passes.h; it holds every nonzero voxel of the volumes) that the new voxelization did
// not touch (touched bit clear; the bits are 32 KiB at 64^3 and stay in cache, where the records
// a count test would read are cold). The resolve overwrites the others, so afterwards the
// volumes equal a voxelization into cleared volumes, with work in proportion to the occupied
// voxels instead of a transfer clear of the four N^3 volumes, and no store where the occupancy
// did not change.
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = VOXEL_STALE_BINDING_TOUCHED_BITS, std430) readonly buffer TouchedBits { uint touchedBits[]; }; // bit x + N (y + N z)
layout(set = 1, binding = VOXEL_STALE_BINDING_ALBEDO, rgba8) uniform writeonly image3D outAlbedo;
layout(set = 1, binding = VOXEL_STALE_BINDING_NORMAL, rgba8) uniform writeonly image3D outNormal;
layout(set = 1, binding = VOXEL_STALE_BINDING_EMISSION, rgba16f) uniform writeonly image3D outEmission;
layout(set = 1, binding = VOXEL_STALE_BINDING_FACES, r32ui) uniform writeonly uimage3D outFaces;
layout(set = 1, binding = VOXEL_STALE_BINDING_PREVIOUS, std430) readonly buffer Touched { uint touchedHeader[GI_VOXEL_TOUCHED_HEADER]; uint touched[]; };

void main() {
    if (gl_GlobalInvocationID.x >= touchedHeader[3])
        return;
    ivec3 c = ivec3(voxelListUnpack(touched[gl_GlobalInvocationID.x]));
    int n = int(pc.grid.dims.x);
    uint i = uint(c.x + n * (c.y + n * c.z));
    if ((touchedBits[i >> 5u] & (1u << (i & 31u))) != 0u)
        return; // touched again: the resolve writes it
    imageStore(outAlbedo, c, vec4(0.0));
    imageStore(outNormal, c, vec4(0.0));
    imageStore(outEmission, c, vec4(0.0));
    imageStore(outFaces, c, uvec4(0u));
}
