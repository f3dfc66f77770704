#version 460
#extension GL_GOOGLE_include_directive : require
// The first generation of instant radiosity on the light sources themselves: one thread per VPL
// record; the emitter source's records (gi/vpl.h: the light after the punctual ones) each take
// the emissive surfel their table entry names (x) and become a VPL on the emitting surface:
//     position, normal: the surfel's (the side that emits);
//     flux = surfel flux * M / N (each of the N VPLs stands for M / N of the M surfels),
//     a cosine emitter like every VPL: a Lambertian patch of radiance Le and area A sends
//     pi Le A in all, Le A cos per steradian = flux / pi * cos;
//     footprint r^2 = A * M / N / pi, the disc of the emitting area the VPL stands for (the
//     gathers' 1/d^2 clamp: a disc emitter is finite on its axis).
// Its light at a receiver is the emitter's direct illumination, one reflection (docs/vpl.md).
// Without punctual lights no vpl_generate.comp pass writes the buffer first: the other sources'
// slots (bounced generations) are then emptied here, for vpl_bounce.comp to fill.
#include "gi/vpl.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_1D) in;
layout(push_constant) uniform PushBlock { VplEmitterPush pc; };

layout(set = 1, binding = VPL_EMITTER_BINDING_POSITION) uniform sampler2DArray surfelPosition;
layout(set = 1, binding = VPL_EMITTER_BINDING_NORMAL) uniform sampler2DArray surfelNormal;
layout(set = 1, binding = VPL_EMITTER_BINDING_FLUX) uniform sampler2DArray surfelFlux;
layout(set = 1, binding = VPL_EMITTER_BINDING_DIRECTIONS, std430) readonly buffer Directions { vec4 directions[]; };
layout(set = 1, binding = VPL_EMITTER_BINDING_VPLS, std430) writeonly buffer Vpls { VplRecord vpls[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.info.y)
        return;
    VplRecord vpl = VplRecord(vec4(0.0), vec4(0.0, 0.0, 1.0, 0.0), vec4(0.0));
    if (uint(directions[i].w) != pc.info.x) {
        if (pc.info.z != 0u)
            vpls[i] = vpl;
        return;
    }
    uint k = uint(directions[i].x);
    if (k < pc.surfels.x) {
        uint side = pc.surfels.y;
        ivec3 texel = ivec3(int(k % side), int(k / side), 0);
        vec4 p = texelFetch(surfelPosition, texel, 0);
        vec3 n = texelFetch(surfelNormal, texel, 0).xyz;
        if (p.w > 0.0 && dot(n, n) > 0.0) {
            vec4 f = texelFetch(surfelFlux, texel, 0);
            float scale = pc.scale.x;
            vpl.position = vec4(p.xyz, 1.0);
            vpl.direction = vec4(normalize(n), 0.0);
            vpl.flux = vec4(f.rgb * scale, f.w * scale * (1.0 / GI_VPL_PI));
        }
    }
    vpls[i] = vpl;
}
