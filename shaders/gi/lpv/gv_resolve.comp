#version 460
// Geometry volume resolve: fixed-point sums of the RSM (slot 0) and camera (slot 1) surfels ->
// blocking-potential SH, combined by max: the source with the larger band-0 coefficient (more
// coverage) wins the whole cell, so a surface seen from both is counted once.
#extension GL_GOOGLE_include_directive : require
#include "gi/lpv_passes.h"

layout(local_size_x = LPV_LOCAL_SIZE_X, local_size_y = LPV_LOCAL_SIZE_Y, local_size_z = LPV_LOCAL_SIZE_Z) in;
layout(push_constant) uniform PushBlock { LpvInjectPush pc; };
layout(set = 1, binding = LPV_GEOMETRY_VOLUME_BINDING_SUMS, std430) readonly buffer GeometryVolumeSums { int data[]; } sums;
layout(set = 1, binding = LPV_GEOMETRY_VOLUME_BINDING_OUTPUT, rgba16f) uniform writeonly image3D geometryVolume;

vec4 load(int cell) {
    int base = LPV_INJECT_HEADER_INTS + 4 * cell;
    return vec4(sums.data[base], sums.data[base + 1], sums.data[base + 2], sums.data[base + 3]) / pc.params.x;
}

void main() {
    ivec3 g = ivec3(gl_GlobalInvocationID);
    ivec3 size = pc.grid.size.xyz + 1;
    if (any(greaterThanEqual(g, size)))
        return;
    int cell = g.x + size.x * (g.y + size.y * g.z);
    vec4 rsm = load(cell), camera = load(cell + size.x * size.y * size.z);
    imageStore(geometryVolume, g, rsm.x >= camera.x ? rsm : camera);
}
