#version 460
#extension GL_GOOGLE_include_directive : require
// Vertex pulling for every rasterising pass (G-buffer, shadow map, RSM): one draw per instance,
// the instance index in push constants, vertices read from the scene's vertex buffer.
#include "raster.h"

void main() {
    rasterVertex();
}
