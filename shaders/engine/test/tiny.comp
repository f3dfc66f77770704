#version 460
#extension GL_GOOGLE_include_directive : require
// Render-graph overhead benchmark: the smallest useful dispatch (one group adds to a counter).
#include "engine/test_bindings.h"
layout(local_size_x = 1) in;
layout(set = 1, binding = ENGINE_TINY_BINDING_COUNTER, std430) buffer Counter { uint value[]; };

void main() { value[0] += 1u; }
