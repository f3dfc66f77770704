// Voxel direct light (Villegas & Ramirez's deferred voxel shading), per facing direction:
// the faces of an occupied voxel that look towards direction d (+X, -X, +Y, -Y, +Z, -Z; the
// faces volume says which are present) reflect the punctual lights as a Lambertian surface,
//   L_d = albedo / pi * sum_l E_l * max(n_d . l, 0) * V_l(n_d) + Le,
// with E_l the light's illuminance at the voxel centre (KHR_lights_punctual: I / d^2 for
// point/spot, lux for directional) and V_l its visibility, marched through the occupancy from
// one voxel off along n_d, or (voxel_light_shadow_map.comp, GI_VOXEL_LIGHT_SHADOW_MAP) looked up
// in the shadow atlas. n_d is the voxel's mean normal where its faces agree (one-sided surface,
// |mean normal| >= 1/2) and d points to that side; otherwise (both faces of a thin wall or roof,
// or the far side of a corner) the axis itself. The level-0 views of the directional volume
// then show each side's own light: a roof voxel lit from above looks lit from above and dark
// from below, where the isotropic voxel of before showed the interior its sunlit top.
#include "engine/lights.h"
#include "engine/scene_types.h"
#include "gi/vct_passes.h"
#ifdef GI_VOXEL_LIGHT_SHADOW_MAP
#include "gi/direct_types.h"
#endif

layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // one invocation per occupied voxel (indirect)
layout(push_constant) uniform Push { VoxelLightPush pc; };

layout(set = 1, binding = VCT_LIGHT_BINDING_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(set = 1, binding = VCT_LIGHT_BINDING_EMISSION, rgba16f) uniform readonly image3D emissionVol;
#ifdef GI_VOXEL_LIGHT_SOFT
layout(set = 1, binding = VCT_LIGHT_BINDING_OCCUPANCY) uniform sampler3D albedoVol; // a = occupancy; linear filtering for soft shadows
vec4 albedoAt(ivec3 c) { return texelFetch(albedoVol, c, 0); }
#else
// The hard march and the shadow-map variant read single texels: a storage image, whose loads
// lavapipe serves far faster than texelFetch through a sampler.
layout(set = 1, binding = VCT_LIGHT_BINDING_OCCUPANCY, rgba8) uniform readonly image3D albedoVol; // a = occupancy
vec4 albedoAt(ivec3 c) { return imageLoad(albedoVol, c); }
#endif
layout(set = 1, binding = VCT_LIGHT_BINDING_DIRECTIONAL, rgba16f) uniform writeonly image2DArray directionalOut; // level 0 of the directional volume
layout(set = 1, binding = VCT_LIGHT_BINDING_LIST, std430) readonly buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint voxels[]; };
layout(set = 1, binding = VCT_LIGHT_BINDING_FACES, r32ui) uniform readonly uimage3D facesVol;
layout(set = 1, binding = VCT_LIGHT_BINDING_WRITTEN, r8ui) uniform uimage3D writtenVol; // the axes stored last time (vct_passes.h)
#if !defined(GI_VOXEL_LIGHT_SOFT) && !defined(GI_VOXEL_LIGHT_SHADOW_MAP)
// The list buffer (VCT_LIGHT_BINDING_LIST) again, as R32_UINT texels, for the hard march's
// occupancy bits: lavapipe loads an SSBO word per lane in a loop with a branch each, a texel
// without.
layout(set = 1, binding = VCT_LIGHT_BINDING_LIST_WORDS, r32ui) uniform readonly uimageBuffer listWords;
#endif
#ifdef GI_VOXEL_LIGHT_SHADOW_MAP
layout(set = 1, binding = VCT_LIGHT_BINDING_LIGHT_SHADOWS, std430) readonly buffer LightShadows { GpuLightShadow lightShadows[]; };
layout(set = 1, binding = VCT_LIGHT_BINDING_SHADOW_VIEWS, std430) readonly buffer ShadowViews { GpuShadowView shadowViews[]; };
layout(set = 1, binding = VCT_LIGHT_BINDING_SHADOW_ATLAS) uniform sampler2DArray shadowAtlas; // point-sampled: the stored depths

// The atlas layer of light i that holds point q of this grid: a directional light's window
// fitted to this grid's box (pc.info.w = 1 + the window's index, gi/direct_types.h) when the
// atlas has it, else the light's own layer (its cube face for a point light).
uint shadowLayer(uint i, GpuLightShadow ls, vec3 q) {
    if (pc.info.w != 0u && pc.info.w <= ls.cascades.w)
        return ls.cascades.z + pc.info.w - 1u;
    uint layer = ls.info.x;
    if (ls.info.z == GI_SHADOW_CUBE)
        layer += cubeFace(q - lights[i].positionType.xyz);
    return layer;
}

// One atlas layer as the taps read it: its view and the world directions along which its u and v
// grow, scaled so that a change of c = 2 uv - 1 by 1 moves that many metres (row k / |row k|^2).
struct AtlasLayer {
    uint layer;
    GpuShadowView view;
    vec3 du, dv;
};
AtlasLayer atlasLayer(uint layer) {
    AtlasLayer l;
    l.layer = layer;
    l.view = shadowViews[layer];
    mat4 m = l.view.viewProj;
    vec3 row0 = vec3(m[0][0], m[1][0], m[2][0]), row1 = vec3(m[0][1], m[1][1], m[2][1]);
    l.du = row0 / dot(row0, row0);
    l.dv = row1 / dot(row1, row1);
    return l;
}

// World point of the stored depth d (layer units) at atlas coordinate uv of a perspective layer:
// the distance from the eye along the ray through uv.
vec3 shadowPerspectivePoint(AtlasLayer l, vec2 uv, float d) {
    mat4 m = l.view.viewProj;
    vec3 ray = vec3(m[0][3], m[1][3], m[2][3]) + (2.0 * uv.x - 1.0) * l.du + (2.0 * uv.y - 1.0) * l.dv;
    return l.view.eye.xyz + (d * l.view.eye.w) * normalize(ray);
}

// Light i's first surface on the ray from world point q towards the light (unit dir): where it
// lies (s, metres towards the light: q + s dir) and which way it faces (the unit normal on the
// light's side, through the stored surface points of the 2x2 texels around q). The stored depth
// is the nearest of the four texels', unfiltered.
struct ShadowHit {
    float s;
    vec3 normal;
};
ShadowHit shadowHitAlongRay(AtlasLayer l, vec3 q, vec3 dir) {
    vec4 clip = l.view.viewProj * vec4(q, 1.0);
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    bool ortho = l.view.eye.w <= 0.0;
    float depth = ortho ? clip.z : distance(q, l.view.eye.xyz) / l.view.eye.w;
    // Gathered texels: x (i0, j1), y (i1, j1), z (i1, j0), w (i0, j0), centred at uv00 + (i, j) / res.
    vec4 d = textureGather(shadowAtlas, vec3(uv, float(l.layer)), 0);
    float res = l.view.texel.z;
    vec2 f = fract(uv * res - 0.5);
    float nearest = f.x < 0.5 ? (f.y < 0.5 ? d.w : d.x) : (f.y < 0.5 ? d.z : d.y);
    ShadowHit hit;
    // Depth grows away from the light, linearly in metres (texel.y metres per unit).
    hit.s = (depth - nearest) * l.view.texel.y;
    // The surface through the four texels' points, from its diagonals (00 -> 11, 10 -> 01). An
    // orthographic layer is linear in uv and depth: one texel is 2 / res along du and dv.
    vec3 diag0 = (2.0 / res) * (l.du + l.dv) + (d.w - d.y) * l.view.texel.y * dir;
    vec3 diag1 = (2.0 / res) * (l.dv - l.du) + (d.z - d.x) * l.view.texel.y * dir;
    if (!ortho) {
        vec2 uv00 = (floor(uv * res - 0.5) + 0.5) / res;
        vec3 p00 = shadowPerspectivePoint(l, uv00, d.w), p11 = shadowPerspectivePoint(l, uv00 + 1.0 / res, d.y);
        vec3 p10 = shadowPerspectivePoint(l, uv00 + vec2(1.0, 0.0) / res, d.z);
        vec3 p01 = shadowPerspectivePoint(l, uv00 + vec2(0.0, 1.0) / res, d.x);
        diag0 = p11 - p00;
        diag1 = p01 - p10;
    }
    vec3 normal = cross(diag0, diag1);
    hit.normal = normalize(dot(normal, dir) < 0.0 ? -normal : normal);
    return hit;
}

// Visibility of light i from the surface with unit normal n in the voxel with centre p (world;
// unit toLight, n . toLight > 0) in the direct-light shadow atlas (gi/direct_types.h): the share
// of the light's rays that reach the voxel's surface. The rays through kShadowTaps points spread
// over the voxel (a 3D low-discrepancy set, so that no light direction lines them up) meet the
// light's first surface (the atlas's stored depth) inside the voxel, beyond it (the ray crossed
// the voxel without meeting its surface: no say), or before it.
// - Lit: inside, on a surface that faces n within 60 degrees. The other surfaces of a voxel (the
//   sunlit outside of a wall whose voxel also holds the floor inside) are not the one lit along
//   n. A hit whose 2x2 texels give a normal nearly across the ray (a depth edge between two
//   surfaces, or a surface the light grazes) counts as facing: its normal says nothing.
// - The lit hits locate the surface: the plane with normal n through their mean.
// - Blocked: a ray stopped before the voxel, if it would have met that plane inside the voxel;
//   one that would have crossed it outside (a point under a floor whose ray leaves through the
//   voxel's side and meets the same floor one voxel on) has no say. A surface inside the voxel
//   that does not face n blocks only in front of the plane: a pier's side face behind the plane
//   of its front face is beside the front face, not in its way.
// Whatever the voxel's size, the test reads the surfaces themselves: no lookup point is moved off
// the voxel past walls a coarse voxel is thicker than, and a sunlit patch that a sub-voxel
// opening casts on a floor counts by its share. Inside / before / beyond take a margin of a
// texel's footprint (the stored depth of a tilted surface varies across a texel) and a fiftieth
// of a voxel; a surface on the voxel's face is inside it. Without a lit hit the voxel is
// shadowed if any ray is blocked, lit if none.
const uint kShadowTaps = 16u;
// A hit faces the surface's normal n within 60 degrees; its normal is unknown when it is within
// about 9 degrees of the ray's perpendicular.
const float kShadowFacing = 0.5, kShadowEdgeOn = 0.15;
// Tap t of the voxel (in [0, 1]^3): x stratified, y and z radical inverses.
vec3 shadowTap(uint t) {
    return vec3((float(t) + 0.5) / float(kShadowTaps), float(bitfieldReverse(t)) * 2.3283064e-10,
                fract(float(t) * 0.6180340 + 0.3));
}
float shadowMapVisibility(uint i, vec3 p, vec3 n, vec3 toLight) {
    GpuLightShadow ls = lightShadows[i];
    if (ls.info.z == GI_SHADOW_NONE)
        return 1.0;
    float a = pc.grid.originSize.w;
    vec3 lightPos = lights[i].positionType.xyz;
    bool directional = uint(lights[i].positionType.w) == GI_LIGHT_DIRECTIONAL;
    // The layer at the voxel's centre serves every tap, but a cube face each tap's own.
    bool cube = ls.info.z == GI_SHADOW_CUBE;
    AtlasLayer layer = atlasLayer(shadowLayer(i, ls, p));
    GpuShadowView view0 = layer.view;
    float texel = view0.eye.w <= 0.0 ? view0.texel.x : view0.texel.x * max(distance(p, lightPos), 1e-6);
    float margin = 1.5 * texel + 0.02 * a;
    vec3 boxLo = p - (0.5 * a + margin), boxHi = p + (0.5 * a + margin);
    float lit = 0.0, litHeight = 0.0;
    uint blockedTaps = 0u; // bit t: tap t's ray is stopped before the voxel, or inside it by a
                           // surface that does not face n
    // The heights along n of those inside the voxel, 4 bits a tap (0..15 for -a..a; 15 for a
    // ray stopped before the voxel, which blocks wherever the plane lies).
    uvec2 beside = uvec2(0u);
    for (uint t = 0u; t < kShadowTaps; ++t) {
        vec3 q = p + (shadowTap(t) - 0.5) * a;
        vec3 dir = directional ? toLight : normalize(lightPos - q);
        // The ray q + s dir is inside the box for s in [s0, s1], s0 <= 0 <= s1.
        vec3 inv = 1.0 / mix(vec3(1e-20), dir, greaterThan(abs(dir), vec3(1e-20)));
        vec3 lo = (boxLo - q) * inv, hi = (boxHi - q) * inv;
        float s0 = max(max(min(lo.x, hi.x), min(lo.y, hi.y)), min(lo.z, hi.z));
        float s1 = min(min(max(lo.x, hi.x), max(lo.y, hi.y)), max(lo.z, hi.z));
        if (!directional)
            s1 = min(s1, distance(lightPos, q)); // a light inside the voxel
        ShadowHit hit = shadowHitAlongRay(cube ? atlasLayer(shadowLayer(i, ls, q)) : layer, q, dir);
        bool inside = hit.s >= s0 && hit.s <= s1;
        bool facing = dot(hit.normal, n) >= kShadowFacing || dot(hit.normal, dir) < kShadowEdgeOn;
        float height = dot(q + hit.s * dir - p, n);
        lit += inside && facing ? 1.0 : 0.0;
        litHeight += inside && facing ? height : 0.0;
        blockedTaps |= hit.s > s1 || (inside && !facing) ? 1u << t : 0u;
        uint quantized = inside && !facing ? uint(clamp((height / a + 1.0) * 7.5 + 0.5, 0.0, 15.0)) : 15u;
        beside[t >> 3u] |= quantized << (4u * (t & 7u));
    }
    if (lit == 0.0)
        return blockedTaps != 0u ? 0.0 : 1.0;
    // Blocked rays that would have met the plane at height h inside the voxel; the voxel's own
    // surfaces not facing n only in front of it.
    float h = litHeight / lit, blocked = 0.0;
    float cosine = dot(n, toLight);
    for (uint left = blockedTaps; left != 0u; left &= left - 1u) {
        uint t = uint(findLSB(left));
        vec3 q = p + (shadowTap(t) - 0.5) * a;
        vec3 meets = q + ((h - dot(q - p, n)) / cosine) * toLight;
        bool inVoxel = all(greaterThanEqual(meets, boxLo)) && all(lessThanEqual(meets, boxHi));
        float height = (float((beside[t >> 3u] >> (4u * (t & 7u))) & 15u) / 7.5 - 1.0) * a;
        blocked += inVoxel && height >= h - a / 7.5 ? 1.0 : 0.0;
    }
    return lit / (lit + blocked);
}
#endif

const float kPi = 3.14159265358979;
// March step (voxels): half a voxel samples every voxel a ray crosses at least once.
const float kShadowStep = 0.5;
// The march starts this far (voxels) off the voxel centre along the normal, so that the voxel
// itself and its neighbours in the same wall do not shadow it.
const float kShadowStart = 1.0;

#ifndef GI_VOXEL_LIGHT_SHADOW_MAP
#ifndef GI_VOXEL_LIGHT_SOFT
// The plain march's stop rule at sample t: at or past the light, out of the grid (floor as an
// unsigned: q < 0 wraps to a huge value) or in the light's voxel.
bool marchStops(vec3 p, vec3 dir, float t, float tMax, ivec3 lightVoxel, uint res) {
    ivec3 v = ivec3(floor(p + t * dir));
    return !(t < tMax) || any(greaterThanEqual(uvec3(v), uvec3(res))) || v == lightVoxel;
}
#endif

// Visibility along p + t * dir, t in [start, tMax) (voxel units), tMax at the light. The
// light's own voxel never blocks it, as the receiver's own voxel does not (the march starts
// off it): a surface inside that voxel lies within a voxel of the light, closer than the grid
// resolves which side of it the light is on. The Cornell lights hang 1 cm under the ceiling;
// at 32^3 (1.77 cm voxels) the ceiling's voxels hold the light and the march shadowed most
// of the box (mean indirect 0.57 of the path tracer's, against 0.92 with the shadow map).
float visibility(vec3 p, vec3 dir, float tMax) {
    ivec3 lightVoxel = ivec3(floor(p + tMax * dir));
#ifdef GI_VOXEL_LIGHT_SOFT
    float n = float(pc.grid.dims.x);
    float transmit = 1.0;
    for (float t = kShadowStart; t < tMax; t += kShadowStep) {
        vec3 q = p + t * dir;
        if (any(lessThan(q, vec3(0.0))) || any(greaterThanEqual(q, vec3(n))) || ivec3(floor(q)) == lightVoxel)
            break;
        // Soft: trilinear occupancy as partial opacity, so edges get a one-voxel penumbra.
        transmit *= 1.0 - textureLod(albedoVol, q / n, 0.0).a;
        if (transmit < 1e-3)
            return 0.0;
    }
    return transmit;
#else
    // Occupancy from the list's bits (gi/vct_passes.h), equal to albedo.a > 0 and cheaper
    // per step than an image load; 4^3 blocks without any occupied voxel are skipped. Each
    // iteration costs the same whatever it does (lavapipe runs both sides of a branch), so the
    // per-ray work is done once before the loop and the loop tests nothing else per sample.
    uint res = pc.grid.dims.x, log2Res = pc.grid.dims.y, log2Quarter = log2Res - 2u;
    uint bits = GI_VOXEL_LIST_HEADER + voxelListBitsOffset(res), coarseBits = GI_VOXEL_LIST_HEADER + voxelListCoarseBitsOffset(res);
    // 1 / dir, a near-zero component (which never reaches a plane) a huge t of its own sign.
    bvec3 up = greaterThanEqual(dir, vec3(0.0));
    vec3 invDir = mix(vec3(1.0) / dir, mix(vec3(-1e30), vec3(1e30), up), lessThan(abs(dir), vec3(1e-20)));
    // The plain march stops at its first sample that is out of the grid, in the light's voxel or
    // at t >= tMax. Each of these holds from its first sample on (the computed p + t dir is
    // monotonic in t per component, and no sample before tMax lies beyond the light's voxel), so
    // the end is found once per ray: stepped from an estimate (where the ray leaves the grid)
    // to the first stopping sample.
    if (marchStops(p, dir, kShadowStart, tMax, lightVoxel, res))
        return 1.0;
    vec3 tGrid = (mix(vec3(0.0), vec3(float(res)), up) - p) * invDir;
    float tEstimate = min(tMax, min(tGrid.x, min(tGrid.y, tGrid.z)));
    float tEnd = kShadowStart + max(ceil((tEstimate - kShadowStart) / kShadowStep), 1.0) * kShadowStep;
    while (marchStops(p, dir, tEnd - kShadowStep, tMax, lightVoxel, res))
        tEnd -= kShadowStep;
    while (!marchStops(p, dir, tEnd, tMax, lightVoxel, res))
        tEnd += kShadowStep;
    // In an empty 4^3 block (and, inside an occupied one, in an empty voxel) the march jumps to
    // its last sample whose exact position lies at least kSkipMargin inside the block's (voxel's)
    // exit planes: t = (4 b + exitOffset) / dir per axis.
    // Rounding moves the computed positions and exit times by < 1e-3 voxels (t < 2^10,
    // N <= 256), so that sample's computed position lies in the block, and by monotonicity so do the
    // samples jumped over: the samples tested are exactly those the plain march finds occupied
    // or not, and the result is the same (the light's block too: no sample before tMax leaves it).
    const float kSkipMargin = 1.0 / 64.0;
    vec3 exitT = (mix(vec3(kSkipMargin), vec3(4.0 - kSkipMargin), up) - p) * invDir;
    vec3 exitVoxelT = (mix(vec3(kSkipMargin), vec3(1.0 - kSkipMargin), up) - p) * invDir;
    // One load per iteration: a sample outside the block last found occupied reads its block's
    // bit; if set, the block is remembered and the same sample runs again reading its voxel's
    // bit, as do the following samples inside that block (one per voxel crossed).
    uint knownCoarse = ~0u;
    // Pre-filtered grids (dims.w = 1): an occupied voxel lets 1 - fill of the light by (its fill,
    // the share of its cross-section its surfaces block, "Pre-filtered opacity"), once per voxel
    // crossed, as the cones' views do; otherwise the first occupied voxel blocks the ray.
    bool prefiltered = pc.grid.dims.w != 0u;
    float transmit = 1.0;
    for (float t = kShadowStart; t < tEnd; t += kShadowStep) {
        // Samples before tEnd lie in the grid (q >= 0): truncation is floor.
        uvec3 v = uvec3(ivec3(p + t * dir));
        uvec3 b = v >> 2u;
        uint coarse = b.x | (b.y << log2Quarter) | (b.z << (2u * log2Quarter));
        uint i = v.x | (v.y << log2Res) | (v.z << (2u * log2Res));
        bool fine = coarse == knownCoarse;
        uint bit = fine ? i : coarse;
        bool set = (imageLoad(listWords, int((fine ? bits : coarseBits) + (bit >> 5u))).x & (1u << (bit & 31u))) != 0u;
        if (fine && set) {
            transmit *= prefiltered ? 1.0 - imageLoad(emissionVol, ivec3(v)).a : 0.0;
            if (transmit < 1e-3)
                return 0.0;
        }
        vec3 tAxis = vec3(fine ? v : b << 2u) * invDir + (fine ? exitVoxelT : exitT);
        float tExit = min(tAxis.x, min(tAxis.y, tAxis.z));
        float tSkip = max(t, t + floor((tExit - t) / kShadowStep) * kShadowStep);
        knownCoarse = set ? coarse : knownCoarse;
        t = !fine && set ? t - kShadowStep : tSkip;
    }
    return transmit;
#endif
}
#endif

// Light i at voxel centre pWorld: the unit direction towards it, its distance (1e30 for a
// directional light) and its illuminance e on a surface facing it (before visibility).
void lightAt(uint i, vec3 pWorld, out vec3 toLight, out float dist, out float e) {
    GpuLight light = lights[i];
    uint type = uint(light.positionType.w);
    if (type == GI_LIGHT_DIRECTIONAL) {
        toLight = -light.directionRange.xyz;
        dist = 1e30;
        e = light.colorIntensity.w;
        return;
    }
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

// Irradiance (rgb) of a surface with unit normal `normal` at voxel centre pGrid / pWorld.
vec3 irradianceAt(vec3 pGrid, vec3 pWorld, vec3 normal) {
    vec3 pMarch = pGrid + normal * kShadowStart;
    vec3 irradiance = vec3(0.0);
    for (uint i = 0u; i < pc.info.x; ++i) {
        vec3 toLight;
        float dist, e;
        lightAt(i, pWorld, toLight, dist, e);
        float cosine = max(dot(normal, toLight), 0.0);
        if (e * cosine <= 0.0)
            continue;
#ifdef GI_VOXEL_LIGHT_SHADOW_MAP
        float v = shadowMapVisibility(i, pWorld, normal, toLight);
#else
        float v = visibility(pMarch, toLight, dot(pGrid + dist * pc.grid.scales.x * toLight - pMarch, toLight));
#endif
        irradiance += lights[i].colorIntensity.rgb * (e * cosine * v);
    }
    return irradiance;
}

// Whether a kept voxel's light, for the surface with unit normal `normal`, is what the level's
// last relight computed (docs/vct.md "Clipmap", moving a level: the light). The march of each
// light that reaches the surface samples p + t dir for t in [kShadowStart, tEnd), tEnd at the
// light or where the ray leaves the grid across an axis the level did not move along (both
// corners' grids end there). If those samples stay a voxel (rounding; the soft march's filter)
// inside the kept box along the moved axes, they read the same occupancy as before the move; a
// march that reaches the new slabs, or left through the slices that left the level, may not.
// (The shadow-map variant keeps no voxel: its atlas follows the camera.)
bool marchesUnchanged(vec3 pGrid, vec3 pWorld, vec3 normal) {
#ifdef GI_VOXEL_LIGHT_SHADOW_MAP
    return false;
#else
    const float kMargin = 1.0;
    float n = float(pc.grid.dims.x);
    vec3 lo = vec3(pc.keepLo.xyz), hi = vec3(pc.keepHi.xyz + 1);
    bvec3 moved = bvec3(vec3(greaterThan(lo, vec3(0.0))) + vec3(lessThan(hi, vec3(n))));
    vec3 pMarch = pGrid + normal * kShadowStart;
    for (uint i = 0u; i < pc.info.x; ++i) {
        vec3 dir;
        float dist, e;
        lightAt(i, pWorld, dir, dist, e);
        if (e * max(dot(normal, dir), 0.0) <= 0.0)
            continue;
        float tEnd = dot(pGrid + dist * pc.grid.scales.x * dir - pMarch, dir);
        for (int k = 0; k < 3; ++k)
            if (!moved[k] && abs(dir[k]) > 1e-20)
                tEnd = min(tEnd, ((dir[k] > 0.0 ? n : 0.0) - pMarch[k]) / dir[k]);
        if (tEnd <= kShadowStart)
            continue; // no sample
        vec3 first = pMarch + kShadowStart * dir, last = pMarch + tEnd * dir;
        for (int k = 0; k < 3; ++k)
            if (moved[k] && (min(first[k], last[k]) < lo[k] + kMargin || max(first[k], last[k]) > hi[k] - kMargin))
                return false;
    }
    return true;
#endif
}

// Stores view v (0..5) of voxel c: what a ray travelling along v sees, the radiance of the faces
// looking back at it (direction v ^ 1, coverage `front`) over the sheets across v's axis k
// (coverage axisCover of the voxel's largest maxCover). See main().
void storeView(ivec3 c, uint v, vec3 faceRadiance, float front, float axisCover, float maxCover, float fill, uint axes,
               uint before) {
    uint k = v >> 1u;
    float alpha = (maxCover > 0.0 ? axisCover / maxCover : 1.0) * fill;
    float shown = front > 0.0 ? min(1.0, 2.0 * front / axisCover) : 0.0;
    // Half-float ceiling: radianceScale maps the brightest light to GI_VOXEL_RADIANCE_TARGET,
    // 16x below it; clamping keeps the volume finite whatever happens.
    vec3 rgb = min(faceRadiance, vec3(65000.0)) * (alpha * shown);
    imageStore(directionalOut, vctDirectionalTexel(c, v, pc.grid.dims.x), (axes & (1u << k)) != 0u ? vec4(rgb, alpha) : vec4(0.0));
}

void main() {
    if (gl_GlobalInvocationID.x >= header[3])
        return;
    ivec3 c = ivec3(voxelListUnpack(voxels[gl_GlobalInvocationID.x]));
    uint faces = imageLoad(facesVol, c).x;
    vec3 albedo = albedoAt(c).rgb;
    // Coverage of the faces looking towards +X, +Y, +Z (pos) and -X, -Y, -Z (neg).
    vec3 coverPos = vec3(voxelFaceCoverage(faces, 0u), voxelFaceCoverage(faces, 2u), voxelFaceCoverage(faces, 4u));
    vec3 coverNeg = vec3(voxelFaceCoverage(faces, 1u), voxelFaceCoverage(faces, 3u), voxelFaceCoverage(faces, 5u));
    vec3 meanNormal = coverPos - coverNeg;
    // One-sided: the faces mostly agree (a flat or gently curved surface, a box edge seen from
    // outside); the mean normal then lights every direction on its side, as a single surface.
    bool oneSided = dot(meanNormal, meanNormal) >= 0.25;
    vec3 mean = oneSided ? normalize(meanNormal) : vec3(0.0);
    vec3 pGrid = vec3(c) + 0.5;
    vec3 pWorld = pc.grid.originSize.xyz + pGrid * pc.grid.originSize.w;
    vec3 emission = (pc.info.z & GI_VOXEL_LIGHT_EMISSION) != 0u ? imageLoad(emissionVol, c).rgb : vec3(0.0);
    vec3 scale = albedo / kPi * pc.grid.scales.y;

    // Radiance of the faces looking towards each direction d (those present, bit d; 0 where
    // absent): the directions on the mean normal's side (dot(axis, mean) > 0) share one
    // irradiance with the mean normal, the others use their own axis. Each distinct normal is
    // evaluated once, in a loop over those the voxel needs (llvmpipe runs a loop as often as
    // its busiest lane needs: once for most voxels, where a loop over the six directions ran
    // the light loop six times, masked).
    uvec3 pos = uvec3(greaterThan(coverPos, vec3(0.0))), neg = uvec3(greaterThan(coverNeg, vec3(0.0)));
    uint present = pos.x | (neg.x << 1u) | (pos.y << 2u) | (neg.y << 3u) | (pos.z << 4u) | (neg.z << 5u);
    uvec3 meanPos = uvec3(greaterThan(mean, vec3(0.0))), meanNeg = uvec3(lessThan(mean, vec3(0.0)));
    uint meanDirs = present & (meanPos.x | (meanNeg.x << 1u) | (meanPos.y << 2u) | (meanNeg.y << 3u) | (meanPos.z << 4u) | (meanNeg.z << 5u));
    uint todo = (present & ~meanDirs) | (meanDirs != 0u ? 64u : 0u);
    // A voxel a moved clipmap level kept holds its views from before the move (shifted in). If
    // none of its marches can read what the move changed, they stay: the list's clear zeroed its
    // record of stored axes, which its unchanged faces restore. Otherwise it is lit as a new voxel.
    if (all(greaterThanEqual(c, pc.keepLo.xyz)) && all(lessThanEqual(c, pc.keepHi.xyz))) {
        bool unchanged = true;
        for (uint left = todo; left != 0u; left &= left - 1u) {
            uint j = uint(findLSB(left)), k = j >> 1u;
            vec3 axis = mix(vec3(0.0), vec3((j & 1u) == 0u ? 1.0 : -1.0), equal(uvec3(k), uvec3(0u, 1u, 2u)));
            unchanged = unchanged && marchesUnchanged(pGrid, pWorld, j == 6u ? mean : axis);
        }
        if (unchanged) {
            imageStore(writtenVol, c, uvec4(voxelViewAxes(faces)));
            return;
        }
    }
    vec3 r0 = vec3(0.0), r1 = vec3(0.0), r2 = vec3(0.0), r3 = vec3(0.0), r4 = vec3(0.0), r5 = vec3(0.0);
    while (todo != 0u) {
        uint j = uint(findLSB(todo));
        todo &= todo - 1u;
        uint k = j >> 1u;
        vec3 axis = mix(vec3(0.0), vec3((j & 1u) == 0u ? 1.0 : -1.0), equal(uvec3(k), uvec3(0u, 1u, 2u)));
        uint dirs = j == 6u ? meanDirs : 1u << j;
        vec3 r = scale * irradianceAt(pGrid, pWorld, j == 6u ? mean : axis) + emission;
        r0 = (dirs & 1u) != 0u ? r : r0;
        r1 = (dirs & 2u) != 0u ? r : r1;
        r2 = (dirs & 4u) != 0u ? r : r2;
        r3 = (dirs & 8u) != 0u ? r : r3;
        r4 = (dirs & 16u) != 0u ? r : r4;
        r5 = (dirs & 32u) != 0u ? r : r5;
    }

    // Level-0 views. A ray travelling along direction v crosses the sheets perpendicular to
    // its axis k; their opacity is the faces' coverage along k relative to the voxel's largest
    // (a flat sheet is opaque seen face-on and transparent edge-on; one at 45 degrees opaque from
    // both axes it spans: its projection fills both). The ray sees the faces looking back at
    // it (direction v ^ 1), in proportion to their share of that axis's coverage: a closed thin
    // wall (equal front and back) shows its front, a one-sided sheet seen from behind is black
    // (its back is the inside of a closed surface), like the path tracer's one-sided faces.
    vec3 axisCover = coverPos + coverNeg;
    float maxCover = max(max(axisCover.x, axisCover.y), axisCover.z);
    // Pre-filtered opacity (dims.w = 1): the share of the voxel's cross-section its surfaces
    // block scales every view (gi/voxel_grid.h), so a sub-voxel column is partly transparent
    // instead of a whole opaque voxel; otherwise a touched voxel is opaque along its largest axis.
    float fill = pc.grid.dims.w != 0u ? imageLoad(emissionVol, c).a : 1.0;
    // The views stored: those with opacity > 0 (gi/vct_passes.h), and, once, zeros into the
    // views of the axes stored last time that the voxel's faces (re-voxelized) no longer cover.
    uint axes = voxelViewAxes(faces), before = imageLoad(writtenVol, c).x;
    if (before != axes)
        imageStore(writtenVol, c, uvec4(axes));
    // A view the voxel's sheets are edge-on to (alpha 0) stays (0, 0): it depends on the
    // faces alone, so it was zeroed when the faces changed (or by the first clear). The axes
    // stored run one loop iteration each (two views): one for a flat wall, where six masked
    // stores (llvmpipe runs a store for the batch whatever its mask) ran for every voxel.
    uint storeAxes = axes | before;
    while (storeAxes != 0u) {
        uint k = uint(findLSB(storeAxes));
        storeAxes &= storeAxes - 1u;
        float pk = k == 0u ? coverPos.x : (k == 1u ? coverPos.y : coverPos.z);
        float nk = k == 0u ? coverNeg.x : (k == 1u ? coverNeg.y : coverNeg.z);
        float ak = k == 0u ? axisCover.x : (k == 1u ? axisCover.y : axisCover.z);
        vec3 rPos = k == 0u ? r0 : (k == 1u ? r2 : r4), rNeg = k == 0u ? r1 : (k == 1u ? r3 : r5);
        storeView(c, 2u * k, rNeg, nk, ak, maxCover, fill, axes, before);
        storeView(c, 2u * k + 1u, rPos, pk, ak, maxCover, fill, axes, before);
    }
}
