#version 460
#extension GL_GOOGLE_include_directive : require
// The first pass of the visibility march's empty-space distance (gi/vpl.h, gi/vpl_visibility.h):
// one thread per block of GI_VPL_VISIBILITY_BLOCK^3 voxels, 0 when any of them is occupied (the
// albedo volume's a, or any half-voxel bit of the camera-centred grid's emission volume), else
// GI_VPL_VISIBILITY_MAX_DISTANCE: the distance before the passes along the axes.
#include "gi/vpl.h"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

layout(set = 1, binding = VPL_DISTANCE_BINDING_INPUT) uniform sampler3D occupancy;
layout(set = 1, binding = VPL_DISTANCE_BINDING_OUTPUT, r8ui) uniform writeonly uimage3D distanceOut;

void main() {
    ivec3 b = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(b, imageSize(distanceOut))))
        return;
    ivec3 base = b * GI_VPL_VISIBILITY_BLOCK;
    bool occupied = false;
    for (int z = 0; z < GI_VPL_VISIBILITY_BLOCK; ++z)
        for (int y = 0; y < GI_VPL_VISIBILITY_BLOCK; ++y)
            for (int x = 0; x < GI_VPL_VISIBILITY_BLOCK; ++x)
                occupied = occupied || texelFetch(occupancy, base + ivec3(x, y, z), 0).a > 0.0;
    imageStore(distanceOut, b, uvec4(occupied ? 0u : GI_VPL_VISIBILITY_MAX_DISTANCE));
}
