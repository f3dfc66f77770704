#version 460
#extension GL_GOOGLE_include_directive : require
// Render-graph test: fills mip 0 of an R32UI image with value = x + width * y.
#include "engine/test_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push {
    uvec4 size; // x, y = image size
} pc;
layout(set = 1, binding = ENGINE_FILL_BINDING_TARGET, r32ui) uniform writeonly uimage2D dst;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(p, pc.size.xy)))
        return;
    imageStore(dst, ivec2(p), uvec4(p.x + pc.size.x * p.y));
}
