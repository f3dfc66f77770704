// Punctual light falloff shared by the rasteriser (GLSL) and the path tracer (C++), so both
// use the same KHR_lights_punctual model: intensity in candela (point/spot) or lux
// (directional), inverse-square falloff, optional range window, smooth spot cone.
// Literals carry the f suffix: GLSL accepts it, and glm's templates need one type in C++.
#ifndef VKGI_ENGINE_LIGHTS_H
#define VKGI_ENGINE_LIGHTS_H
#include "../shared/bridge.h"

GI_NAMESPACE_BEGIN

#define GI_LIGHT_DIRECTIONAL 0u
#define GI_LIGHT_POINT 1u
#define GI_LIGHT_SPOT 2u
// A Lambertian point source standing for emissive surfaces: intensity times max(0, cos) about
// directionRange.xyz. Never in a scene's light buffer: only the RSM of the LPV's emitter proxies
// (rsm.frag; docs/lpv.md, "Emissive surfaces") renders it.
#define GI_LIGHT_EMITTER 3u

// glTF's recommended range window: 1 inside, smoothly 0 at `range`; range <= 0 means infinite.
GI_INLINE float lightRangeWindow(float dist, float range) {
    if (range <= 0.0f)
        return 1.0f;
    float r = dist / range;
    float r4 = r * r * r * r;
    float w = clamp(1.0f - r4, 0.0f, 1.0f);
    return w * w;
}

// Smooth spot attenuation as in the glTF spec: 0 outside the outer cone, 1 inside the inner
// cone, squared linear ramp in cos(angle) between them. `cosAngle` = dot(spotDir, -toLightDir).
GI_INLINE float spotConeAttenuation(float cosAngle, float cosInner, float cosOuter) {
    float scale = 1.0f / max(0.001f, cosInner - cosOuter);
    float t = clamp((cosAngle - cosOuter) * scale, 0.0f, 1.0f);
    return t * t;
}

GI_NAMESPACE_END
#endif
