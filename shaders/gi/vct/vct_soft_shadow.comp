#version 460
#extension GL_GOOGLE_include_directive : require
// Cone-traced soft shadows (VctSettings::softShadows, pass gi.vct.shadow): the direct light of
// the punctual lights over the G-buffer,
//   L = Le + albedo / pi * sum_l E_l * max(n . l, 0) * V_l,
// as the deferred pass (shaders/gi/direct/deferred.comp) computes it, with V_l the visibility of
// a cone of half-angle shadowAperture from the pixel towards light l through the voxel opacity
// (coneVisibility in voxel_cone.glsl) REPLACING the shadow-map visibility: the cone already sees
// every occluder the grid resolves, so multiplying both would darken twice. The penumbra widens
// with the aperture: at distance t from the receiver the cone is 2 t tan(aperture) wide.
// Output in nits, the same layout as the deferred pass's image (DirectData::direct).
#include "engine/lights.h"
#include "engine/scene_types.h"
#include "gi/vct_passes.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push { VctShadowPush pc; };
#include "voxel_cone.glsl"
layout(set = 1, binding = VCT_SHADOW_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(set = 1, binding = VCT_SHADOW_BINDING_NORMAL, rgba16f) uniform readonly image2D gNormal;
layout(set = 1, binding = VCT_SHADOW_BINDING_ALBEDO, rgba16f) uniform readonly image2D gAlbedo;
layout(set = 1, binding = VCT_SHADOW_BINDING_EMISSION, rgba32f) uniform readonly image2D gEmission;
layout(set = 1, binding = VCT_SHADOW_BINDING_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(set = 1, binding = VCT_SHADOW_BINDING_DIRECT, rgba32f) uniform writeonly image2D outDirect;

const float kPi = 3.14159265358979;

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(px), pc.info.yz)))
        return;
    vec4 position = imageLoad(gPosition, px);
    if (position.w == 0.0) {
        imageStore(outDirect, px, vec4(0.0, 0.0, 0.0, 1.0));
        return;
    }
    vec3 p = position.xyz;
    vec3 normal = normalize(imageLoad(gNormal, px).xyz);
    vec3 albedo = imageLoad(gAlbedo, px).rgb;
    vec3 radiance = imageLoad(gEmission, px).rgb;
    float n = float(pc.grid.dims.x);
    // Grid units; the cone starts one voxel off the surface, as the diffuse cones do.
    vec3 origin = (p - pc.grid.originSize.xyz) * pc.grid.scales.x + normal;
    for (uint i = 0u; i < pc.info.x; ++i) {
        GpuLight light = lights[i];
        uint type = uint(light.positionType.w);
        vec3 toLight;
        float e, tEnd;
        if (type == GI_LIGHT_DIRECTIONAL) {
            toLight = -light.directionRange.xyz;
            e = light.colorIntensity.w;
            tEnd = 1.7321 * n; // across the grid
        } else {
            vec3 d = light.positionType.xyz - p;
            float dist2 = max(dot(d, d), 1e-12);
            float dist = sqrt(dist2);
            toLight = d / dist;
            e = light.colorIntensity.w * lightRangeWindow(dist, light.directionRange.w) / dist2;
            if (type == GI_LIGHT_SPOT)
                e *= spotConeAttenuation(dot(light.directionRange.xyz, -toLight), light.cone.x, light.cone.y);
            // From the offset origin to the light, in voxels.
            tEnd = dot(light.positionType.xyz - (pc.grid.originSize.xyz + (origin / pc.grid.scales.x)), toLight) *
                   pc.grid.scales.x;
        }
        float cosine = max(dot(normal, toLight), 0.0);
        if (e * cosine <= 0.0)
            continue;
        float v = coneVisibility(origin, toLight, cosine, pc.cones.cone.w, pc.cones.cone.y, tEnd, n);
        radiance += albedo / kPi * light.colorIntensity.rgb * (e * cosine * v);
    }
    imageStore(outDirect, px, vec4(radiance, 1.0));
}
