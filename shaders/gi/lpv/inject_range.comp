#version 460
// LPV injection, pass 1: the frame's largest RSM texel flux M (max over colour channels), the
// unit every stored SH value is divided by (gi/lpv_passes.h). Positive floats order like
// their bit patterns, so an integer atomicMax finds it; one atomic per subgroup.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "gi/lpv_passes.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform PushBlock { LpvInjectPush pc; };
layout(set = 1, binding = LPV_INJECT_BINDING_POSITION, rgba32f) uniform readonly image2DArray rsmPosition;
layout(set = 1, binding = LPV_INJECT_BINDING_FLUX, rgba32f) uniform readonly image2DArray rsmFlux;
layout(set = 1, binding = LPV_INJECT_BINDING_BUFFER, std430) buffer Injection { uint header[LPV_INJECT_HEADER_INTS]; } injection;

void main() {
    ivec3 t = ivec3(gl_GlobalInvocationID);
    float m = 0.0;
    if (all(lessThan(t, ivec3(pc.rsm.xx, pc.rsm.y))) && imageLoad(rsmPosition, t).w > 0.0) {
        vec3 flux = imageLoad(rsmFlux, t).rgb;
        m = max(max(flux.r, flux.g), flux.b);
        if (!(m < 3.0e38)) // NaN or Inf flux is bad input: ignore the texel
            m = 0.0;
    }
    m = subgroupMax(m);
    if (subgroupElect() && m > 0.0)
        atomicMax(injection.header[0], floatBitsToUint(m));
}
