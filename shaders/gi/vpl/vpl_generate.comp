#version 460
#extension GL_GOOGLE_include_directive : require
// One thread per VPL: a light's Halton direction (local frame, precomputed on the CPU, with the
// light's index in w; the table is in the interleaved subset order of gi/vpl.h; slots of bounced
// generations, source index >= the light count, are left empty for vpl_bounce.comp)
// is turned into world space, projected into the light's RSM layer, and the surface found there
// becomes the VPL: position on that surface's plane along the exact Halton ray (so it moves
// continuously with the light), its normal, and the flux of the solid angle it stands for,
//     flux = rsmFlux / texelSolidAngle * (coneSolidAngle / N) = albedo * I(w) * coneSolidAngle / N.
// A directional light's layer is orthographic (view.eye.w = 0): its sample is a Halton point of
// the window in normalised device coordinates, the ray starts there on the near plane and runs
// along the light, and the VPL stands for 1/N of the window's area A = texelArea * res^2:
//     flux = rsmFlux / texelArea * (A / N) = rsmFlux * res^2 / N = albedo * E * A / N.
// In a window much larger than the focus radius the CPU gives the points instead
// (focusedWindowPoints, vkgi/vpl.hpp): NDC xy, and in z the window area the point stands for;
// points fixed to the world, denser around the camera. Points beyond the window stay empty.
// Each VPL also records the area of surface it stands for, (solid angle / N) d^2 / cos or
// (A / N) / cos, as the squared radius of a disc of that area: the gathers clamp 1/d^2 at a
// multiple of it (a disc emitter of that radius is finite on its axis; a point is not).
#include "gi/direct_types.h"
#include "gi/vpl.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_1D) in;
const float kMinFootprintCos = 0.25;
layout(push_constant) uniform PushBlock { VplGeneratePush pc; };

layout(set = 1, binding = VPL_GENERATE_BINDING_RSM_POSITION) uniform sampler2DArray rsmPosition;
layout(set = 1, binding = VPL_GENERATE_BINDING_RSM_NORMAL) uniform sampler2DArray rsmNormal;
layout(set = 1, binding = VPL_GENERATE_BINDING_RSM_FLUX) uniform sampler2DArray rsmFlux;
layout(set = 1, binding = VPL_GENERATE_BINDING_SHADOW_VIEWS, std430) readonly buffer ShadowViews {
    GpuShadowView shadowViews[];
};
layout(set = 1, binding = VPL_GENERATE_BINDING_LIGHTS, std430) readonly buffer Lights { VplLight lights[]; };
layout(set = 1, binding = VPL_GENERATE_BINDING_DIRECTIONS, std430) readonly buffer Directions { vec4 directions[]; };
layout(set = 1, binding = VPL_GENERATE_BINDING_VPLS, std430) writeonly buffer Vpls { VplRecord vpls[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.info.y)
        return;
    uint source = uint(directions[i].w);
    if (source >= pc.info.x) {
        // A bounced generation's slot (vpl.bounces > 1): vpl_bounce.comp writes it.
        vpls[i] = VplRecord(vec4(0.0), vec4(0.0, 0.0, 1.0, 0.0), vec4(0.0));
        return;
    }
    VplLight light = lights[source];
    vec3 local = directions[i].xyz;
    uint layer = light.info.z;
    GpuShadowView view = shadowViews[layer];
    bool ortho = view.eye.w == 0.0;
    vec3 origin, dir;
    bool inWindow = true;
    float shareArea = 0.0; // focused window: the window area this VPL stands for (m^2)
    if (ortho) {
        mat4 inv = inverse(view.viewProj);
        if (local.z > 0.0) {
            shareArea = local.z;
            inWindow = all(lessThanEqual(abs(local.xy), vec2(1.0)));
        }
        vec4 nearPoint = inv * vec4(local.xy, 0.0, 1.0);
        origin = nearPoint.xyz / nearPoint.w;
        dir = view.axisArea.xyz;
    } else {
        dir = normalize(light.axisX.xyz * local.x + light.axisY.xyz * local.y + light.axisZ.xyz * local.z);
        layer += light.info.w == 6u ? cubeFace(dir) : 0u;
        view = shadowViews[layer];
        origin = light.position.xyz;
    }
    vec4 clip = view.viewProj * vec4(origin + dir, 1.0);
    VplRecord vpl;
    vpl.position = vec4(origin, 0.0);
    vpl.direction = vec4(0.0, 0.0, 1.0, 0.0);
    vpl.flux = vec4(0.0);
    if (clip.w > 0.0 && inWindow) {
        float res = view.texel.z;
        vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
        ivec2 texel = clamp(ivec2(floor(uv * res)), ivec2(0), ivec2(int(res) - 1));
        vec4 p = texelFetch(rsmPosition, ivec3(texel, layer), 0);
        if (p.w > 0.0) {
            vec3 n = normalize(texelFetch(rsmNormal, ivec3(texel, layer), 0).xyz);
            vec3 flux = texelFetch(rsmFlux, ivec3(texel, layer), 0).rgb;
            // The texel's surface plane along the exact ray; fall back to the texel centre when
            // the ray grazes the plane or lands more than ~2 texels away from it (texel.x is a
            // size per metre of distance in a perspective layer, in metres in an orthographic one).
            float texelDist = ortho ? 1.0 : distance(p.xyz, origin);
            float denom = dot(dir, n);
            float t = abs(denom) > 1e-4 ? dot(p.xyz - origin, n) / denom : -1.0;
            float tolerance = 2.0 * view.texel.x * texelDist + 1e-6;
            vec3 hit = (t > 0.0 && distance(origin + t * dir, p.xyz) < tolerance) ? origin + t * dir : p.xyz;
            float scale, footprint;
            // Grazing surfaces: the footprint stops growing at kMinFootprintCos (their flux is
            // small there anyway, and an unbounded clamp would darken a whole wall).
            float cosSurface = max(-dot(dir, n), kMinFootprintCos);
            if (ortho) {
                float share = shareArea > 0.0 ? shareArea : light.position.w * view.axisArea.w * res * res;
                scale = share / view.axisArea.w;
                footprint = share / cosSurface;
            } else {
                float cosAxis = max(dot(normalize(p.xyz - origin), view.axisArea.xyz), 1e-3);
                scale = light.position.w / rsmTexelSolidAngle(view.axisArea.w, cosAxis);
                vec3 toHit = hit - origin;
                footprint = light.position.w * dot(toHit, toHit) / cosSurface;
            }
            vpl.position = vec4(hit, 1.0);
            vpl.direction = vec4(n, 0.0);
            vpl.flux = vec4(flux * scale, footprint * (1.0 / GI_VPL_PI));
        }
    }
    vpls[i] = vpl;
}
