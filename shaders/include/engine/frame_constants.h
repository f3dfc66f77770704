// Per-frame constants (set 0, binding 0, a uniform buffer), shared by C++ and GLSL. Every
// pipeline's set 0 is this one layout, so one descriptor set per frame serves all passes.
#ifndef VKGI_ENGINE_FRAME_CONSTANTS_H
#define VKGI_ENGINE_FRAME_CONSTANTS_H
#include "../shared/bridge.h"

#define GI_FRAME_SET 0
#define GI_FRAME_BINDING 0

GI_NAMESPACE_BEGIN

GI_GPU_STRUCT(FrameConstants) {
    mat4 view;
    mat4 proj;
    mat4 viewProj;
    mat4 invViewProj;
    vec4 cameraPosition; // xyz world position, w = vertical field of view (radians)
    uvec4 resolution;    // x width, y height, z frame index, w light count
    vec4 sceneMin;       // xyz scene bounds minimum, w = time in seconds
    vec4 sceneMax;       // xyz scene bounds maximum, w = 0
};
GI_CHECK_SIZE(FrameConstants, 320);
GI_CHECK_OFFSET(FrameConstants, cameraPosition, 256);

GI_NAMESPACE_END

#ifndef __cplusplus
layout(set = GI_FRAME_SET, binding = GI_FRAME_BINDING, std140) uniform FrameConstantsBlock {
    FrameConstants frame;
};
#endif

#endif
