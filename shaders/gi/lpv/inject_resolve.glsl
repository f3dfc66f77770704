// LPV injection, pass 3: fixed-point sums -> float SH in the first wavefront and in the
// accumulation volume (which starts as the injected light).
#extension GL_GOOGLE_include_directive : require
#include "gi/lpv_passes.h"

layout(local_size_x = LPV_LOCAL_SIZE_X, local_size_y = LPV_LOCAL_SIZE_Y, local_size_z = LPV_LOCAL_SIZE_Z) in;
layout(push_constant) uniform PushBlock { LpvInjectPush pc; };
layout(set = 1, binding = LPV_RESOLVE_BINDING_BUFFER, std430) readonly buffer Injection { int data[]; } injection;
layout(set = 1, binding = LPV_RESOLVE_BINDING_WAVEFRONT_R, LPV_FORMAT) uniform writeonly image3D wavefrontR;
layout(set = 1, binding = LPV_RESOLVE_BINDING_WAVEFRONT_G, LPV_FORMAT) uniform writeonly image3D wavefrontG;
layout(set = 1, binding = LPV_RESOLVE_BINDING_WAVEFRONT_B, LPV_FORMAT) uniform writeonly image3D wavefrontB;
layout(set = 1, binding = LPV_RESOLVE_BINDING_ACCUMULATION_R, LPV_FORMAT) uniform writeonly image3D accumulationR;
layout(set = 1, binding = LPV_RESOLVE_BINDING_ACCUMULATION_G, LPV_FORMAT) uniform writeonly image3D accumulationG;
layout(set = 1, binding = LPV_RESOLVE_BINDING_ACCUMULATION_B, LPV_FORMAT) uniform writeonly image3D accumulationB;

vec4 load(int base) {
    return vec4(injection.data[base], injection.data[base + 1], injection.data[base + 2], injection.data[base + 3]) /
           pc.params.x;
}

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    ivec3 size = pc.grid.size.xyz;
    if (any(greaterThanEqual(p, size)))
        return;
    int base = LPV_INJECT_HEADER_INTS + LPV_INJECT_CELL_INTS * (p.x + size.x * (p.y + size.y * p.z));
    vec4 r = load(base), g = load(base + 4), b = load(base + 8);
    imageStore(wavefrontR, p, r);
    imageStore(wavefrontG, p, g);
    imageStore(wavefrontB, p, b);
    imageStore(accumulationR, p, r);
    imageStore(accumulationG, p, g);
    imageStore(accumulationB, p, b);
}
