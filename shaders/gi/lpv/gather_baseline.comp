#version 460
// Benchmark baseline only (not used by the engine): the plain 6-neighbour gather the LPV step's
// cost is compared with (../shared/LAVAPIPE.md: 3 RGBA16F SH images in, 3 out, one 4x4 matrix
// per neighbour and colour, no accumulation, no occlusion).
#extension GL_GOOGLE_include_directive : require
#include "gi/lpv.h"

layout(local_size_x = LPV_LOCAL_SIZE_X, local_size_y = LPV_LOCAL_SIZE_Y, local_size_z = LPV_LOCAL_SIZE_Z) in;
layout(push_constant) uniform PushBlock { LpvPropagatePush pc; };
layout(set = 1, binding = LPV_PROPAGATE_BINDING_SOURCE_R, rgba16f) uniform readonly image3D sourceR;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_SOURCE_G, rgba16f) uniform readonly image3D sourceG;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_SOURCE_B, rgba16f) uniform readonly image3D sourceB;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_TARGET_R, rgba16f) uniform writeonly image3D targetR;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_TARGET_G, rgba16f) uniform writeonly image3D targetG;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_TARGET_B, rgba16f) uniform writeonly image3D targetB;

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    ivec3 size = pc.gridSize.xyz;
    if (any(greaterThanEqual(p, size)))
        return;
    vec4 sumR = vec4(0.0), sumG = vec4(0.0), sumB = vec4(0.0);
    for (int i = 0; i < 6; ++i) {
        ivec3 q = clamp(p - lpvAxisStep(i), ivec3(0), size - 1);
        mat4 m = mat4(pc.params.x + float(i));
        sumR += m * imageLoad(sourceR, q);
        sumG += m * imageLoad(sourceG, q);
        sumB += m * imageLoad(sourceB, q);
    }
    imageStore(targetR, p, sumR);
    imageStore(targetG, p, sumG);
    imageStore(targetB, p, sumB);
}
