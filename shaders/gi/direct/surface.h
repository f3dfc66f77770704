// Fragment-side material lookup shared by the G-buffer and RSM shaders (GLSL only).
#ifndef VKGI_GI_DIRECT_SURFACE_H
#define VKGI_GI_DIRECT_SURFACE_H
#include "engine/scene_types.h"
#include "gi/direct_types.h"

layout(set = 1, binding = DIRECT_RASTER_BINDING_TEXTURES) uniform sampler2DArray baseColorTextures;

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) flat in uint inMaterial;
layout(location = 4) flat in vec4 inBaseColor; // the material, read per vertex (raster.h)
layout(location = 5) flat in vec4 inEmission;
layout(location = 6) flat in vec4 inMaterialParams;

GpuMaterial surfaceMaterial() {
    return GpuMaterial(inBaseColor, inEmission, inMaterialParams);
}

// False for scenes without textures (a pipeline variant): lavapipe runs the texture branch
// masked on every fragment whether or not any lane takes it, so only a constant removes it.
layout(constant_id = 0) const bool kSceneHasTextures = true;

// Lambertian albedo as the path tracer defines it: baseColor x texture, clamped to [0,1].
vec3 surfaceAlbedo(GpuMaterial m) {
    vec4 base = m.baseColor;
    if (kSceneHasTextures && m.params.z >= 0.0)
        base *= texture(baseColorTextures, vec3(inUv, m.params.z));
    return clamp(base.rgb, 0.0, 1.0);
}

// Unit shading normal turned towards `viewer` (reflection is two-sided). A normal that
// interpolates to ~zero falls back to the geometric normal from screen derivatives.
vec3 surfaceNormal(vec3 viewer) {
    vec3 n = inNormal;
    if (dot(n, n) < 1e-12)
        n = cross(dFdx(inPosition), dFdy(inPosition));
    n = normalize(n);
    return dot(n, viewer - inPosition) < 0.0 ? -n : n;
}
#endif
