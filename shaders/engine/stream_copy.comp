#version 460
#extension GL_GOOGLE_include_directive : require
// Streaming probe of vkgi-bench: copies a buffer 16 bytes per invocation, the memory-bound
// pattern that every "bytes moved / time" ratio of the bench is compared with.
#include "engine/test_bindings.h"
layout(local_size_x = 64) in;
layout(push_constant) uniform Push {
    uvec4 count; // x = uvec4 elements
} pc;
layout(set = 1, binding = ENGINE_STREAM_COPY_BINDING_SOURCE, std430) readonly buffer Src { uvec4 src[]; };
layout(set = 1, binding = ENGINE_STREAM_COPY_BINDING_TARGET, std430) writeonly buffer Dst { uvec4 dst[]; };

void main() {
    uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
    if (i < pc.count.x)
        dst[i] = src[i];
}
