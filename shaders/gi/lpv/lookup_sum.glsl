// LPV lookup, pass 0: the channel sum R + G + B of the accumulated SH volume, which the lookup's
// damping reads (one trilinear fetch per damping point instead of three). Included by
// lookup_sum_<format>.comp, which defines LPV_FORMAT (the accumulation's storage format).
#extension GL_GOOGLE_include_directive : require
#include "gi/lpv_passes.h"

layout(local_size_x = LPV_LOCAL_SIZE_X, local_size_y = LPV_LOCAL_SIZE_Y, local_size_z = LPV_LOCAL_SIZE_Z) in;
layout(push_constant) uniform PushBlock { LpvInjectPush pc; };
layout(set = 1, binding = LPV_SUM_BINDING_ACCUMULATION_R, LPV_FORMAT) uniform readonly image3D accumulationR;
layout(set = 1, binding = LPV_SUM_BINDING_ACCUMULATION_G, LPV_FORMAT) uniform readonly image3D accumulationG;
layout(set = 1, binding = LPV_SUM_BINDING_ACCUMULATION_B, LPV_FORMAT) uniform readonly image3D accumulationB;
layout(set = 1, binding = LPV_SUM_BINDING_OUTPUT, LPV_FORMAT) uniform writeonly image3D outSum;

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(p, pc.grid.size.xyz)))
        return;
    imageStore(outSum, p, imageLoad(accumulationR, p) + imageLoad(accumulationG, p) + imageLoad(accumulationB, p));
}
