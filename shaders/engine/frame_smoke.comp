#version 460
// Copies a few FrameConstants fields to a buffer so a test can compare them exactly.
#extension GL_GOOGLE_include_directive : require
#include "engine/frame_constants.h"
#include "engine/test_bindings.h"
layout(local_size_x = 1) in;
layout(set = 1, binding = ENGINE_FRAME_SMOKE_BINDING_VALUES, std430) writeonly buffer Out { vec4 values[]; };
void main() {
    values[0] = frame.viewProj[3];
    values[1] = frame.cameraPosition;
    values[2] = vec4(frame.resolution);
    values[3] = frame.sceneMax;
}
