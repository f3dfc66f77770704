#version 460
#extension GL_GOOGLE_include_directive : require
// Smoke test of the compute path: push constants, a specialization constant, a storage
// buffer and a storage image, all with exactly predictable results.
#include "engine/test_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(constant_id = 0) const uint kScale = 1;
layout(push_constant) uniform Push {
    uvec4 size;   // x, y = image size
    uvec4 offset; // x = value added to every element
} pc;
layout(set = 1, binding = ENGINE_SMOKE_BINDING_VALUES, std430) writeonly buffer Out { uint values[]; };
layout(set = 1, binding = ENGINE_SMOKE_BINDING_IMAGE, r32ui) uniform writeonly uimage2D img;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(p, pc.size.xy)))
        return;
    uint i = p.y * pc.size.x + p.x;
    values[i] = i * kScale + pc.offset.x;
    imageStore(img, ivec2(p), uvec4(p.x * 1000u + p.y));
}
