#version 460
#extension GL_GOOGLE_include_directive : require
// vkgi-view: linear radiance (RGBA32F composite) to the 8-bit UNORM swapchain image, with the
// tone map of vkgi/image_io.hpp (exposure, Narkowicz's ACES fit, sRGB OETF; NaN/Inf ->
// magenta), so the window shows what the screenshot PNG stores. The composite may be smaller
// than the window while a resize is pending: pixels outside it are black.
#include "view/tonemap_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push {
    uvec4 size;   // x, y = swapchain size; z, w = composite size
    vec4 params;  // x = exposure, y = 1 for ACES, 0 for clamp
} pc;
layout(set = 1, binding = VIEW_TONEMAP_BINDING_COMPOSITE, rgba32f) uniform readonly image2D composite;
layout(set = 1, binding = VIEW_TONEMAP_BINDING_TARGET, rgba8) uniform writeonly image2D target;

float aces(float v) {
    return clamp(v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14), 0.0, 1.0);
}

float srgbOetf(float f) {
    return f <= 0.0031308 ? 12.92 * f : 1.055 * pow(f, 1.0 / 2.4) - 0.055;
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(p), pc.size.xy)))
        return;
    vec3 rgb = vec3(0.0);
    if (all(lessThan(uvec2(p), pc.size.zw))) {
        vec3 radiance = imageLoad(composite, p).rgb;
        if (any(isnan(radiance)) || any(isinf(radiance))) {
            imageStore(target, p, vec4(1.0, 0.0, 1.0, 1.0));
            return;
        }
        for (int c = 0; c < 3; ++c) {
            float v = max(pc.params.x * radiance[c], 0.0);
            float f = pc.params.y > 0.5 ? aces(v) : clamp(v, 0.0, 1.0);
            rgb[c] = srgbOetf(f);
        }
    }
    imageStore(target, p, vec4(rgb, 1.0));
}
