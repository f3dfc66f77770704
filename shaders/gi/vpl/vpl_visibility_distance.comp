#version 460
#extension GL_GOOGLE_include_directive : require
// The passes along the axes of the visibility march's empty-space distance (gi/vpl.h,
// gi/vpl_visibility.h): one thread per block, along the axis pc.axis, d(b) = min over offsets k of
// max(|k|, d'(b + k axis)) with d' the previous pass's distance (the blocks' 0 or maximum first),
// so that after the passes along x, y and z d is the max-norm distance in blocks to the nearest
// occupied block (at most GI_VPL_VISIBILITY_MAX_DISTANCE). The search stops at the first |k| no
// smaller than the best so far.
#include "gi/vpl.h"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(push_constant) uniform PushBlock { VplDistancePush pc; };

layout(set = 1, binding = VPL_DISTANCE_BINDING_INPUT) uniform usampler3D distanceIn;
layout(set = 1, binding = VPL_DISTANCE_BINDING_OUTPUT, r8ui) uniform writeonly uimage3D distanceOut;

void main() {
    ivec3 n = imageSize(distanceOut);
    ivec3 v = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(v, n)))
        return;
    ivec3 axis = pc.axis.xyz;
    int best = int(texelFetch(distanceIn, v, 0).r);
    for (int k = 1; k < best; ++k) {
        ivec3 lo = v - k * axis, hi = v + k * axis;
        if (all(greaterThanEqual(lo, ivec3(0))))
            best = min(best, max(k, int(texelFetch(distanceIn, lo, 0).r)));
        if (all(lessThan(hi, n)))
            best = min(best, max(k, int(texelFetch(distanceIn, hi, 0).r)));
    }
    imageStore(distanceOut, v, uvec4(uint(best)));
}
