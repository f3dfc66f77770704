#version 460
// Render-graph overhead benchmark: the smallest useful dispatch (one group adds to a counter).
layout(local_size_x = 1) in;
layout(set = 1, binding = 0, std430) buffer Counter { uint value[]; };

void main() { value[0] += 1u; }
