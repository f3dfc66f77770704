// Voxel direct light (Villegas & Ramirez's deferred voxel shading): every occupied voxel
// reflects the punctual lights as a Lambertian surface with the voxel's mean normal,
//   L = albedo / pi * sum_l E_l * max(n . l, 0) * V_l + Le,
// with E_l the light's illuminance at the voxel centre (KHR_lights_punctual: I / d^2 for
// point/spot, lux for directional) and V_l its visibility, marched through the occupancy, or
// (voxel_light_shadow_map.comp, GI_VOXEL_LIGHT_SHADOW_MAP) looked up in the shadow atlas.
#include "engine/lights.h"
#include "engine/scene_types.h"
#include "gi/voxel_passes.h"
#ifdef GI_VOXEL_LIGHT_SHADOW_MAP
#include "gi/direct_types.h"
#endif

layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // one invocation per occupied voxel (indirect)
layout(push_constant) uniform Push { VoxelLightPush pc; };

layout(set = 1, binding = 0, std430) readonly buffer Lights { GpuLight lights[]; };
layout(set = 1, binding = 2, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = 3, rgba16f) uniform readonly image3D emissionVol;
layout(set = 1, binding = 4) uniform sampler3D albedoVol; // a = occupancy; linear filtering for soft shadows
layout(set = 1, binding = 5, rgba16f) uniform writeonly image3D radianceOut;
layout(set = 1, binding = 6, std430) readonly buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint voxels[]; };
#ifdef GI_VOXEL_LIGHT_SHADOW_MAP
layout(set = 1, binding = 7, std430) readonly buffer LightShadows { GpuLightShadow lightShadows[]; };
layout(set = 1, binding = 8, std430) readonly buffer ShadowViews { GpuShadowView shadowViews[]; };
layout(set = 1, binding = 9) uniform sampler2DArrayShadow shadowAtlas;

// Visibility of light i from voxel centre p (world; unit normal n or zero, unit toLight) in the
// direct-light shadow atlas (gi/direct_types.h), one bilinear compare. Every point of the
// voxel lies within sqrt(3)/2 voxels of its centre, so the lookup point, moved that far
// towards the light, is at least as near the light as any surface inside the voxel: the
// voxel's own surface cannot shadow it. It also moves one voxel along the normal (as the ray
// march starts), off the rest of its wall. The stored first surface may be nearer than the
// lookup point by the depth change across one texel of a tilted surface: one texel footprint
// of bias covers tilts up to 45 degrees.
float shadowMapVisibility(uint i, vec3 p, vec3 n, vec3 toLight) {
    GpuLightShadow ls = lightShadows[i];
    if (ls.info.z == GI_SHADOW_NONE)
        return 1.0;
    vec3 q = p + pc.grid.originSize.w * (n + 0.8660254 * toLight);
    uint layer = ls.info.x;
    if (ls.info.z == GI_SHADOW_CUBE)
        layer += cubeFace(q - lights[i].positionType.xyz);
    GpuShadowView view = shadowViews[layer];
    bool ortho = view.eye.w <= 0.0;
    float texel = ortho ? view.texel.x : view.texel.x * max(dot(q - view.eye.xyz, view.axisArea.xyz), 0.0);
    vec4 clip = view.viewProj * vec4(q, 1.0);
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    float depth = (ortho ? clip.z : distance(q, view.eye.xyz) / view.eye.w) - texel / view.texel.y;
    return texture(shadowAtlas, vec4(uv, float(layer), depth));
}
#endif

const float kPi = 3.14159265358979;
// Mean |cos| between a fixed axis and uniformly distributed directions: the cosine factor of a
// voxel whose normals cancel (a wall seen from both sides), where the facing is unknown.
const float kMeanAbsCos = 0.5;
// March step (voxels): half a voxel samples every voxel a ray crosses at least once.
const float kShadowStep = 0.5;
// The march starts this far (voxels) off the voxel centre along the normal, so that the voxel
// itself and its neighbours in the same wall do not shadow it.
const float kShadowStart = 1.0;

// Visibility along p + t * dir, t in [start, tMax) (voxel units), tMax at the light. The
// light's own voxel never blocks it, as the receiver's own voxel does not (the march starts
// off it): a surface inside that voxel lies within a voxel of the light, closer than the grid
// resolves which side of it the light is on. The Cornell lights hang 1 cm under the ceiling;
// at 32^3 (1.77 cm voxels) the ceiling's voxels hold the light and the march shadowed most
// of the box (mean indirect 0.57 of the path tracer's, against 0.92 with the shadow map).
float visibility(vec3 p, vec3 dir, float tMax, uint mode) {
    float n = float(pc.grid.dims.x);
    float transmit = 1.0;
    ivec3 lightVoxel = ivec3(floor(p + tMax * dir));
    for (float t = kShadowStart; t < tMax; t += kShadowStep) {
        vec3 q = p + t * dir;
        if (any(lessThan(q, vec3(0.0))) || any(greaterThanEqual(q, vec3(n))) || ivec3(floor(q)) == lightVoxel)
            break;
        if (mode == GI_VCT_OCCLUSION_HARD) {
            if (texelFetch(albedoVol, ivec3(q), 0).a > 0.0)
                return 0.0;
        } else {
            // Soft: trilinear occupancy as partial opacity, so edges get a one-voxel penumbra.
            transmit *= 1.0 - textureLod(albedoVol, q / n, 0.0).a;
            if (transmit < 1e-3)
                return 0.0;
        }
    }
    return transmit;
}

void main() {
    if (gl_GlobalInvocationID.x >= header[3])
        return;
    ivec3 c = ivec3(voxelListUnpack(voxels[gl_GlobalInvocationID.x]));
    vec4 albedo = texelFetch(albedoVol, c, 0);
    vec4 nEnc = imageLoad(normalVol, c);
    vec3 normal = voxelNormalDecode(nEnc.xyz);
    bool hasNormal = dot(normal, normal) > 0.25; // encoded zero normals decode to |n| ~ 0
    normal = hasNormal ? normalize(normal) : vec3(0.0);
    vec3 pGrid = vec3(c) + 0.5;
    vec3 pWorld = pc.grid.originSize.xyz + pGrid * pc.grid.originSize.w;
    vec3 pMarch = pGrid + normal * kShadowStart;

    vec3 irradiance = vec3(0.0);
    for (uint i = 0u; i < pc.info.x; ++i) {
        GpuLight light = lights[i];
        uint type = uint(light.positionType.w);
        vec3 toLight;
        float dist, e;
        if (type == GI_LIGHT_DIRECTIONAL) {
            toLight = -light.directionRange.xyz;
            dist = 1e30;
            e = light.colorIntensity.w;
        } else {
            vec3 d = light.positionType.xyz - pWorld;
            // A voxel stands for a patch of area a^2, not for its centre: its mean irradiance is
            // I Omega / a^2, Omega the solid angle of the patch. For a disc of that area facing
            // the light at distance h, Omega = 2 pi (1 - h / sqrt(h^2 + a^2 / pi)): I / h^2 far
            // away, 2 pi I / a^2 at h = 0. I / (h^2 + a^2 / (2 pi)) has both limits (within 8%
            // between them), where the centre value I / h^2 overshoots near a light (a light
            // 1 cm under a ceiling of 1.8 cm voxels: 1.7x).
            float a2 = pc.grid.originSize.w * pc.grid.originSize.w;
            float d2 = dot(d, d);
            dist = sqrt(d2);
            toLight = d / max(dist, 1e-20);
            e = light.colorIntensity.w / (d2 + a2 * (0.5 / kPi)) * lightRangeWindow(dist, light.directionRange.w);
            if (type == GI_LIGHT_SPOT)
                e *= spotConeAttenuation(dot(light.directionRange.xyz, -toLight), light.cone.x, light.cone.y);
        }
        float cosine = hasNormal ? max(dot(normal, toLight), 0.0) : kMeanAbsCos;
        if (e * cosine <= 0.0)
            continue;
#ifdef GI_VOXEL_LIGHT_SHADOW_MAP
        float v = shadowMapVisibility(i, pWorld, normal, toLight);
#else
        float v = visibility(pMarch, toLight, dot(pGrid + dist * pc.grid.scales.x * toLight - pMarch, toLight), pc.info.y);
#endif
        irradiance += light.colorIntensity.rgb * (e * cosine * v);
    }
    vec3 radiance = albedo.rgb / kPi * irradiance * pc.grid.scales.y;
    if ((pc.info.z & GI_VOXEL_LIGHT_EMISSION) != 0u) // off when the scene has no emissive material
        radiance += imageLoad(emissionVol, c).rgb;
    // Half-float ceiling: radianceScale maps the brightest light to GI_VOXEL_RADIANCE_TARGET,
    // 16x below it; clamping keeps the volume finite whatever happens.
    imageStore(radianceOut, c, vec4(min(radiance, vec3(65000.0)), 1.0));
}
