#version 460
#extension GL_GOOGLE_include_directive : require
// Final HDR image = direct + indirect (both linear radiance, nits).
#include "gi/direct_types.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform PushBlock { CompositePush pc; };
// Point reads of storage images (faster on lavapipe than texelFetch through a sampler); every
// technique's indirect image is RGBA32F like the direct one.
layout(set = 1, binding = DIRECT_COMPOSITE_BINDING_DIRECT, rgba32f) uniform readonly image2D direct;
layout(set = 1, binding = DIRECT_COMPOSITE_BINDING_INDIRECT, rgba32f) uniform readonly image2D indirect;
layout(set = 1, binding = DIRECT_COMPOSITE_BINDING_OUTPUT, rgba32f) uniform writeonly image2D outFinal;

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(px), pc.size.xy)))
        return;
    vec3 c = imageLoad(direct, px).rgb + imageLoad(indirect, px).rgb;
    imageStore(outFinal, px, vec4(c, 1.0));
}
