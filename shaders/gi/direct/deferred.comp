#version 460
#extension GL_GOOGLE_include_directive : require
// Deferred direct lighting over the G-buffer: emission + sum over all punctual lights of
// albedo/pi * E * visibility, with E from the shared KHR_lights_punctual falloff (lights.h)
// and visibility from the shadow atlas (PCF over bilinear receiver-plane depth
// compares). The light loop has a run-time trip count so lavapipe's JIT stays small.
#include "engine/lights.h"
#include "engine/scene_types.h"
#include "gi/direct_types.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform PushBlock { DeferredPush pc; };

// The G-buffer as storage images: point reads, which lavapipe serves faster by image load than
// by texelFetch through a sampler.
layout(set = 1, binding = DIRECT_DEFERRED_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(set = 1, binding = DIRECT_DEFERRED_BINDING_NORMAL, rgba16f) uniform readonly image2D gNormal;
layout(set = 1, binding = DIRECT_DEFERRED_BINDING_ALBEDO, rgba16f) uniform readonly image2D gAlbedo;
layout(set = 1, binding = DIRECT_DEFERRED_BINDING_EMISSION, rgba32f) uniform readonly image2D gEmission;
layout(set = 1, binding = DIRECT_DEFERRED_BINDING_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(set = 1, binding = DIRECT_DEFERRED_BINDING_LIGHT_SHADOWS, std430) readonly buffer LightShadows { GpuLightShadow lightShadows[]; };
layout(set = 1, binding = DIRECT_DEFERRED_BINDING_SHADOW_VIEWS, std430) readonly buffer ShadowViews { GpuShadowView shadowViews[]; };
layout(set = 1, binding = DIRECT_DEFERRED_BINDING_SHADOW_ATLAS) uniform sampler2DArray shadowDepth; // point sampler: textureGather of raw depths
layout(set = 1, binding = DIRECT_DEFERRED_BINDING_OUTPUT, rgba32f) uniform writeonly image2D outDirect;

const float kPi = 3.14159265358979;

// Shadow-map texel coordinates (xy, texel centres at +0.5) and stored depth of world point x.
vec3 shadowProject(GpuShadowView view, vec3 x) {
    vec4 clip = view.viewProj * vec4(x, 1.0);
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    float depth = view.eye.w > 0.0 ? distance(x, view.eye.xyz) / view.eye.w : clip.z;
    return vec3(uv * view.texel.z, depth);
}

// Fraction of the PCF kernel that sees the light from `p` (normal `n`, unit `toLight`).
//
// Receiver-plane compares: every shadow texel a tap reads is compared with the depth the
// receiver's tangent plane has at that texel's centre, not with the depth at p. The texel
// stores the first surface at its centre, so for a planar receiver the two are equal where
// nothing occludes it, whatever the incidence angle, and only a constant bias (rounding,
// curvature) is left. A single reference depth per tap needs a slope bias of l tan(theta) for
// texels l away: 10 texels (0.36 m) at the room's 79 degree incidence with the 3x3 kernel, which
// put the lookup behind the thin ceiling and lintel and lit their contact shadows; a normal
// offset l sin(theta) avoids that but shifts every shadow edge sideways by l sin(theta) tan(theta)
// (0.13 m on the room floor). Texels come from a non-compare gather, weighted bilinearly.
float shadowVisibility(uint lightIndex, vec3 p, vec3 n, vec3 toLight) {
    GpuLightShadow ls = lightShadows[lightIndex];
    if (ls.info.z == GI_SHADOW_NONE)
        return 1.0;
    GpuLight light = lights[lightIndex];
    uint layer = ls.info.x;
    if (ls.info.z == GI_SHADOW_CUBE)
        layer += cubeFace(p - light.positionType.xyz);
    // Directional light with cascades: the finest cascade whose box holds the whole footprint
    // (PCF reach, the bilinear tap's texel, the normal offset) around p; the planner sized every
    // box so its slice of the view has that margin. Points outside all of them (beyond the
    // cascades' depth range) keep the whole-scene layer. Coarse to fine, so the finest wins.
    float margin = float(pc.size.w) + pc.bias.x + 1.5;
    for (uint k = ls.cascades.y; k > 0u; --k) {
        uint c = ls.cascades.x + k - 1u;
        vec3 t = shadowProject(shadowViews[c], p);
        float hi = shadowViews[c].texel.z - margin;
        if (all(greaterThanEqual(t.xy, vec2(margin))) && all(lessThanEqual(t.xy, vec2(hi))) && t.z >= 0.0 && t.z <= 1.0)
            layer = c;
    }
    GpuShadowView view = shadowViews[layer];
    bool ortho = view.eye.w <= 0.0;
    // World size of one shadow texel at p, which the biases scale with.
    float texel = ortho ? view.texel.x : view.texel.x * max(dot(p - view.eye.xyz, view.axisArea.xyz), 0.0);
    vec3 q = p + n * (pc.bias.x * texel);
    vec3 c = shadowProject(view, q);
    // The bias is a distance along the normal (rounding of p, the half-float normal, curvature),
    // so along the light it is 1 / cos(theta) longer; at grazing angles the plane's depth across
    // the footprint is also most sensitive to the normal's rounding.
    float cosTheta = max(dot(n, toLight), 0.05);
    float bias = pc.bias.y * texel / (cosTheta * view.texel.y);
    // Orthographic depth is affine, so on the plane it is c.z plus a gradient per texel (found by
    // projecting two tangents one texel long). Perspective depth (distance / far) is not affine
    // in the texel coordinates; there each texel's ray from the light is cut with the plane.
    vec2 grad = vec2(0.0);
    if (ortho) {
        vec3 t1 = normalize(abs(n.x) < 0.9 ? cross(n, vec3(1, 0, 0)) : cross(n, vec3(0, 1, 0)));
        vec3 t2 = cross(n, t1);
        vec3 d1 = shadowProject(view, q + t1 * texel) - c, d2 = shadowProject(view, q + t2 * texel) - c;
        float det = d1.x * d2.y - d2.x * d1.y;
        // Seen edge-on the plane has no defined gradient (and receives no light): compare flat.
        if (abs(det) > 1e-6)
            grad = vec2(d1.z * d2.y - d2.z * d1.y, d2.z * d1.x - d1.z * d2.x) / det;
    }
    // Perspective: the direction w to texel-space point (x, y) satisfies (row0 - ndc.x row3) . w = 0
    // and (row1 - ndc.y row3) . w = 0 (the light position projects to clip (0, 0, *, 0)), so
    // w = cross(row0 - x row3, row1 - y row3) = w0 + x wx + y wy (row3 x row3 = 0): affine in ndc,
    // and ndc = x * 2 / resolution for centred texel coordinates x (texel coordinates - resolution / 2).
    mat4 vpT = transpose(view.viewProj);
    vec3 row0 = vpT[0].xyz, row1 = vpT[1].xyz, row3 = vpT[3].xyz;
    float toNdc = 2.0 / view.texel.z;
    vec3 w0 = cross(row0, row1), wx = cross(row1, row3) * toNdc, wy = cross(row3, row0) * toNdc;
    // Lavapipe runs both sides of every branch, so both projections share one branch-free compare
    // of each gathered texel (centred coordinates x, y) with the plane dot(n, . - q) = 0:
    //   (stored + bias - L) |stored + bias - L| nw^2 >= k |w|^2.
    // Orthographic: L = c.z + grad . ((x, y) - c.xy), nw = 1, k = 0. Perspective (depth = distance /
    // far): the texel's ray w meets the plane at distance |planeDist / nw| |w|, nw = dot(n, w) =
    // nw0 + x nwx + y nwy; L = 0 and k = (planeDist / far)^2 square the compare (stored depths and
    // biases are >= 0), so no square root or division per texel. A ray parallel to the plane
    // (nw^2 <= 1e-24 |w|^2) never meets it: that texel is compared with the receiver's depth c.z.
    float mid = 0.5 * view.texel.z;
    float planeDist = dot(n, q - view.eye.xyz) / view.eye.w;
    float k = ortho ? 0.0 : planeDist * planeDist;
    vec3 nwCoef = ortho ? vec3(1.0, 0.0, 0.0) : vec3(dot(n, w0), dot(n, wx), dot(n, wy));
    float l0 = ortho ? c.z - dot(grad, c.xy - mid) : 0.0;
    // |w|^2 = q0 + x qx + y qy + x^2 qxx + x y qxy + y^2 qyy (zero when orthographic: k = 0).
    vec3 qLin = ortho ? vec3(0.0) : vec3(dot(w0, w0), 2.0 * dot(w0, wx), 2.0 * dot(w0, wy));
    vec3 qSq = ortho ? vec3(0.0) : vec3(dot(wx, wx), dot(wy, wy), 2.0 * dot(wx, wy));
    // The (2r+1)^2 bilinear taps read the (2r+2)^2 texels from c.xy - r - 0.5 on; a texel's
    // weight summed over the taps is separable: 1 - f on the first row/column, f on the last and
    // 1 between. So each texel is gathered and compared once, (r+1)^2 gathers of 2x2 texels
    // instead of 4 (2r+1)^2 compares.
    int r = int(pc.size.w);
    vec2 st = c.xy - float(r) - 0.5; // texel (i, j) has its centre at (i + 0.5, j + 0.5)
    vec2 origin = floor(st), f = st - origin;
    int last = 2 * r + 1;
    float hi = view.texel.z - 0.5;
    float lit = 0.0;
    for (int v = 0; v <= r; ++v) {
        // This gather's two rows: texel centres (clamped to the layer as the sampler's
        // clamp-to-edge does, then centred), weights, and the terms in y alone.
        float by = origin.y + float(2 * v);
        vec2 y = clamp(by + vec2(0.5, 1.5), 0.5, hi) - mid;
        vec2 wgtY = vec2(v == 0 ? 1.0 - f.y : 1.0, 2 * v + 1 == last ? f.y : 1.0);
        vec2 ly = grad.y * y, ny = nwCoef.z * y;
        vec2 qy = y * (qLin.z + y * qSq.y) + qLin.x;
        for (int u = 0; u <= r; ++u) {
            float bx = origin.x + float(2 * u);
            vec4 stored = textureGather(shadowDepth, vec3((vec2(bx, by) + 1.0) / view.texel.z, float(layer)));
            vec2 x = clamp(bx + vec2(0.5, 1.5), 0.5, hi) - mid;
            vec2 wgtX = vec2(u == 0 ? 1.0 - f.x : 1.0, 2 * u + 1 == last ? f.x : 1.0);
            vec2 lx = l0 + grad.x * x, nx = nwCoef.x + nwCoef.y * x;
            vec2 qx = x * (qLin.y + x * qSq.x);
            // Gather order: (0,1), (1,1), (1,0), (0,0) relative to (bx, by).
            vec4 d = stored + bias - (lx.xyyx + ly.yyxx);
            vec4 nw = nx.xyyx + ny.yyxx;
            vec4 len2 = (qx.xyyx + qy.yyxx) + qSq.z * (x.xyyx * y.yyxx);
            vec4 nw2 = nw * nw;
            bvec4 seen = mix(greaterThanEqual(stored, vec4(c.z - bias)), greaterThanEqual(d * abs(d) * nw2, k * len2),
                             greaterThan(nw2, 1e-24 * len2));
            lit += dot(vec4(seen), vec4(wgtX.x * wgtY.y, wgtX.y * wgtY.y, wgtX.y * wgtY.x, wgtX.x * wgtY.x));
        }
    }
    float taps = float((2 * r + 1) * (2 * r + 1));
    return lit / taps;
}

// Irradiance (lux) at p from light i, without shadowing; `toLight` receives the unit direction.
vec3 lightIrradiance(GpuLight light, vec3 p, vec3 n, out vec3 toLight) {
    vec3 radiantI = light.colorIntensity.rgb * light.colorIntensity.w;
    uint type = uint(light.positionType.w);
    if (type == GI_LIGHT_DIRECTIONAL) {
        toLight = -light.directionRange.xyz;
        return radiantI * max(dot(n, toLight), 0.0);
    }
    vec3 d = light.positionType.xyz - p;
    float dist2 = max(dot(d, d), 1e-12);
    float dist = sqrt(dist2);
    toLight = d / dist;
    float atten = lightRangeWindow(dist, light.directionRange.w) / dist2;
    if (type == GI_LIGHT_SPOT)
        atten *= spotConeAttenuation(dot(light.directionRange.xyz, -toLight), light.cone.x, light.cone.y);
    return radiantI * (atten * max(dot(n, toLight), 0.0));
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(px), pc.size.xy)))
        return;
    vec4 position = imageLoad(gPosition, px);
    // One store for background and surface pixels alike: llvmpipe runs an image store as a masked
    // loop over the lanes per channel even where no lane takes the branch it is in.
    vec3 radiance = vec3(0.0);
    if (position.w != 0.0) {
        vec3 p = position.xyz;
        vec3 n = imageLoad(gNormal, px).xyz;
        vec3 albedo = imageLoad(gAlbedo, px).rgb;
        radiance = imageLoad(gEmission, px).rgb;
        for (uint i = 0u; i < pc.size.z; ++i) {
            vec3 toLight;
            vec3 e = lightIrradiance(lights[i], p, n, toLight);
            if (all(equal(e, vec3(0.0))))
                continue;
            radiance += albedo / kPi * e * shadowVisibility(i, p, n, toLight);
        }
    }
    imageStore(outDirect, px, vec4(radiance, 1.0));
}
