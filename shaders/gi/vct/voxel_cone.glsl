// Cone tracing through the voxel radiance (Crassin et al. 2011). It samples the directional
// volume at VCT_CONE_BINDING_DIRECTIONAL, which the includer leaves to it (a 2D array: per
// viewing direction a stack of slices across its axis, level 0 the voxels themselves, level k
// the 2^k-voxel blocks; vct_passes.h). Everything is in grid units (voxels); radiance stays
// scaled by radianceScale.
layout(set = 1, binding = VCT_CONE_BINDING_DIRECTIONAL) uniform sampler2DArray directional;

// Cones start this far (voxels) from their origin, which callers already offset by one voxel
// along the normal: together they clear the surface's own (conservatively thick) voxel.
const float kConeStart = 1.0;
// Accumulated opacity at which a cone stops (the rest would add under 1%).
const float kConeOpaque = 0.99;

// Smallest transmittance 1 - a a stored opacity can express: the largest half float below 1 is
// 1 - 2^-11, so an opaque texel reads as optical depth ln(2^11) ~ 7.6 (transmittance 5e-4).
const float kMinTransmit = 1.0 / 2048.0;

// Per-cone constants of the sampling, computed once per cone instead of once per step.
struct ConeFrame {
    vec3 w;          // |dir|: the weights of the three views' optical depths
    vec3 stack;      // first layer of the view facing dir, per axis (+X,-X,+Y,-Y,+Z,-Z stacks of N)
    vec3 aheadSign;  // the `ahead` slice is aheadSign * floor(aheadSign * q + 0.5) + aheadShift:
    vec3 aheadShift; // ceil(q - 0.5) where dir >= 0, floor(q + 0.5) - 1 where dir < 0
    float n;         // N: layers per view at every level
    float invN;
    int maxLevel;    // log2(N)
};

ConeFrame coneFrame(vec3 dir, float n) {
    ConeFrame f;
    f.w = abs(dir);
    // Stacks are picked by arithmetic, not by branching, so SIMD lanes with different
    // directions still take one path (three fetches instead of up to six).
    f.stack = (vec3(0.0, 2.0, 4.0) + step(dir, vec3(0.0))) * n;
    vec3 forward = step(vec3(0.0), dir);
    f.aheadSign = 1.0 - 2.0 * forward;
    f.aheadShift = forward - 1.0;
    f.n = n;
    f.invN = 1.0 / n;
    f.maxLevel = findMSB(int(n)); // the grid is a power of two
    return f;
}

// 2^k for an integer k in [-126, 127], from the exponent bits (exact; no exp2 polynomial).
float exp2Int(int k) {
    return intBitsToFloat((k + 127) << 23);
}

// Mip level of a sample: the one nearest to the cone's diameter (round(log2(diameter)),
// diameter >= 1), capped at floor(log2(max(reach, 1))) (no self-reads, traceCone) and at the
// coarsest level. Both from the exponent bits instead of log2 per step: adding 2^23 - 0x3504F4
// to the bits carries a mantissa >= sqrt(2) (1 + 0x3504F4 / 2^23 is the first float above it)
// into the exponent, which rounds log2 to the nearest integer.
int coneLevel(float diameter, float reach, int maxLevel) {
    int nearest = (floatBitsToInt(diameter) + 0x4AFB0C) >> 23;
    int below = floatBitsToInt(max(reach, 1.0)) >> 23;
    return min(min(nearest, below) - 127, maxLevel);
}

// Directional sample at p (voxels) of level `level` (texels 2^level = 1 / invSize voxels
// wide) of the directional volume: a = optical depth per texel width along the cone's dir, in
// units of ln 2 (log2 of the transmittance: exp2 of it needs no constant, and the radiance
// weights below are ratios of optical depths, which the unit leaves unchanged), rgb = the
// radiance of what the sample holds times a (the caller divides once, folded into its opacity).
// The voxels are surfaces, i.e. sheets: a path of unit length along dir crosses the sheets
// perpendicular to axis k |dir_k| times as often as a path along k does, so the optical depths
// of the three views facing dir add with weights |dir_k| (Crassin's dir^2 blend of the
// opacities instead gives a floor crossed at 45 degrees the opacity of half its face-on view
// plus half its edge-on view, which thins out level by level: the closed box lost 25-30% of
// its opacity at 64^3, more the finer the grid, i.e. the coarser the level its walls are
// reached at). The radiance is the mean of the views' radiances weighted by what each
// contributes to the extinction, so an opaque face-on view hides the edge-on views behind it.
// `layerBase` is the first layer of the grid's six stacks: 0 for the directional volume, the
// level's in the clipmap volume (vct_passes.h).
vec4 sampleDirectionalAt(ConeFrame f, vec3 p, int level, float invSize, bool ahead, float layerBase) {
    float texels = f.n * invSize; // this level's resolution
    // Each view is read at the centre of its texel along its own axis (filtered across it): a
    // texel of view k is a slab along k whose opacity already integrates what lies along k, so
    // the steps that fall inside it add up to its optical depth. Filtering along k as well
    // turned a one-voxel sheet into a two-texel tent of partial opacities whose optical depths
    // -ln(1 - a) integrate to 2 instead of the sheet's 7.6: 13% of the light crossed every
    // opaque wall (the furnace's "filtering loss"). So the sample of view k is one layer (the
    // slab's slice), filtered bilinearly across the other two axes.
    // Which texel along the view's axis: the one holding the sample, or with `ahead` (gathering
    // cones, levels >= 1) the first whose centre lies ahead of the sample in the travel
    // direction. A view of a texel is what a ray crossing the whole texel along k sees first;
    // a sample past the texel's centre has the texel's first half behind it, and when that half
    // holds a wall's far side the view shows the far side. A 0.2 m wall at 0.1 m voxels is one
    // level-1 texel: cones running along the wall's inner face read its sun-lit outer face
    // (room: corners 3-8x, the ceiling near the window wall ~1.7x too bright; PT-indirect
    // relMSE 0.49 -> 0.19 at 64^3). The texel ahead is the one the step goes on into; the
    // steps (at most one texel, traceCone) still visit every texel along the path, each from
    // the centre before it, so no optical depth is lost or counted twice, only shifted half a
    // texel ahead. Level 0 keeps the texel holding the sample: its half-voxel of near-field
    // occlusion (crevices, concave corners) is what the first steps must see, and a voxel
    // holds no wall's far side next to its near side (walls of two voxels or more). Shadow
    // cones (coneVisibility) keep it at every level: an occluder right at the receiver's side
    // must still shade it.
    vec3 q = p * invSize; // in texels of this level (exact: powers of two)
    vec3 slice = floor(q);
    if (ahead && level > 0)
        slice = f.aheadSign * floor(f.aheadSign * q + 0.5) + f.aheadShift;
    // Beyond the grid every view is empty. Along a view's axis a slice outside [0, texels)
    // (whose layer would belong to another slice or view) weighs 0. Across it the sampler
    // clamps to the edge (lavapipe filters it faster than a border colour) and `edge`
    // restores the transparent border exactly: within half a texel of the grid's face the
    // bilinear taps are the edge texel and one beyond it, which the border makes 0, i.e. the
    // clamped value times the edge texel's weight q + 0.5 (texels + 0.5 - q at the far face);
    // inside the grid the factor is 1. So a sample half a texel or more outside the grid on
    // any axis reads exactly 0 (coneExit relies on it).
    vec3 inside = step(vec3(0.0), slice) * step(slice, vec3(texels - 1.0));
    vec3 edge = clamp(q + 0.5, 0.0, 1.0) * clamp(texels + 0.5 - q, 0.0, 1.0);
    vec3 layer = (f.stack + layerBase) + clamp(slice, vec3(0.0), vec3(texels - 1.0));
    vec3 uvw = p * f.invN;
    float lod = float(level);
    vec4 sx = (inside.x * edge.y * edge.z) * textureLod(directional, vec3(uvw.yz, layer.x), lod);
    vec4 sy = (inside.y * edge.x * edge.z) * textureLod(directional, vec3(uvw.xz, layer.y), lod);
    vec4 sz = (inside.z * edge.x * edge.y) * textureLod(directional, vec3(uvw.xy, layer.z), lod);
    vec3 alpha = vec3(sx.a, sy.a, sz.a);
    // optical depth of one texel seen along each axis, from its stored opacity (units of ln 2)
    vec3 tau = f.w * -log2(max(1.0 - alpha, kMinTransmit));
    // radiance of view k = rgb_k / a_k (premultiplied): one division for the three
    vec3 opacity = max(alpha, 1e-6);
    float inv = 1.0 / (opacity.x * opacity.y * opacity.z);
    vec3 weight = tau * vec3(opacity.y * opacity.z, opacity.x * opacity.z, opacity.x * opacity.y) * inv;
    return vec4(weight.x * sx.rgb + weight.y * sy.rgb + weight.z * sz.rgb, tau.x + tau.y + tau.z);
}

vec4 sampleDirectional(ConeFrame f, vec3 p, int level, float invSize, bool ahead) {
    return sampleDirectionalAt(f, p, level, invSize, ahead, 0.0);
}

// Distance along a cone beyond which every sample lies half a texel or more outside the grid on
// some axis, where it reads exactly 0 (sampleDirectional): stopping there changes no result, and a
// cone leaving the grid no longer steps through empty space up to the grid diagonal (a 30-degree
// cone's own bounds test, |p| beyond the grid by a diameter, never fires once t > 1 / (2 tan)).
// Along the axis j the sample at t is speed_j * t - dist_j past the face ahead (dist_j from the
// origin to it); its texel T = 2^level <= min(N, sqrt(2) * max(1, 2 tanHalf t), max(1, rise t
// / 1.5)) (coneLevel), so T / 2 <= N / 2 and T / 2 <= 0.7072 + beta t with beta the smaller
// slope. Both bounds give a t past which the condition holds for good; margins cover rounding.
float coneExit(vec3 origin, vec3 dir, float rise, float tanHalf, float n) {
    vec3 speed = abs(dir);
    vec3 dist = mix(origin, vec3(n) - origin, step(vec3(0.0), dir));
    float beta = min(1.4143 * tanHalf, max(rise, 0.0) / 3.0);
    vec3 byGrid = (dist + 0.5 * n) / max(speed, 1e-6);
    vec3 byLevel = mix(vec3(1e30), (dist + 0.7072) / max(speed - beta, 1e-6), greaterThan(speed, vec3(beta)));
    vec3 exit = min(byGrid, byLevel);
    return min(min(exit.x, exit.y), exit.z) * 1.001 + 0.01;
}

// Front-to-back accumulation along a cone of half-angle atan(tanHalf). Each sample reads the
// mip level nearest to the cone's diameter d, whose pre-integrated texels are 2^level wide,
// and turns the sample's optical depth per texel width into the opacity of the step s:
// a = 1 - exp(-depth * s / 2^level) (Beer-Lambert; the colour is the sample's radiance * a).
//
// The level is also capped so that the sample's filter never reaches the surface the cone
// starts from. `rise` = dir . n of that surface; the origin is one voxel off it along n, so a
// sample at t is h = 1 + rise * t voxels above it. The surface's voxels reach at most one voxel
// above it, so a texel of width T holding one of them has its centre at most 1 + T / 2 above
// it, and trilinear filtering reads texels whose centres are within T of the sample: the
// surface is out of reach when 1 + T/2 + T <= h, i.e. T <= rise * t / 1.5. Without the cap a
// 30-degree cone (d = 1.15 t) always reaches back to its own surface (T ~ d > t), and grazing
// cones read it at every level: a lit floor added a share of its own direct light to its
// indirect light, a share that grew with the number of levels, i.e. with the grid
// (Cornell indirect relMSE 0.29 / 0.58 / 1.06 at 32^3 / 64^3 / 128^3). At a capped level the
// step is at most one texel, so no texel is stepped over; with d = 2^level the step is the
// usual stepFactor * d.
// `occlusion` gets Villegas' AO: opacity weighted by 1 / (1 + decay * distance).
vec4 traceCone(vec3 origin, vec3 dir, float rise, float tanHalf, float stepFactor, float decay, float n, out float occlusion) {
    ConeFrame f = coneFrame(dir, n);
    vec4 acc = vec4(0.0);
    occlusion = 0.0;
    // the grid diagonal, or where the cone has left the grid for good
    float tMax = min(1.7321 * n, coneExit(origin, dir, rise, tanHalf, n));
    for (float t = kConeStart; t < tMax && acc.a < kConeOpaque;) {
        float diameter = max(1.0, 2.0 * tanHalf * t);
        vec3 p = origin + t * dir;
        if (any(lessThan(p, vec3(-diameter))) || any(greaterThan(p, vec3(n + diameter))))
            break;
        int level = coneLevel(diameter, rise * t / 1.5, f.maxLevel);
        float invSize = exp2Int(-level);
        float stepLength = stepFactor * min(diameter, exp2Int(level));
        vec4 s = sampleDirectional(f, p, level, invSize, true);
        float a = 1.0 - exp2(-s.a * stepLength * invSize);
        acc.rgb += ((1.0 - acc.a) * (s.a > 0.0 ? a / s.a : 0.0)) * s.rgb;
        acc.a += (1.0 - acc.a) * a;
        occlusion += (1.0 - occlusion) * a / (1.0 + decay * t);
        t += stepLength;
    }
    return acc;
}

// Visibility of a point light at distance tEnd (voxels) along dir through the voxel opacity,
// with a cone of half-angle atan(tanHalf): exp of minus the optical depth accumulated as in
// traceCone (same levels, level cap and steps), in [0, 1]. The march stops where the light's
// own voxel begins (as the voxel light's march does): a surface within a voxel of the light
// cannot be resolved as lying in front of it.
float coneVisibility(vec3 origin, vec3 dir, float rise, float tanHalf, float stepFactor, float tEnd, float n) {
    ConeFrame f = coneFrame(dir, n);
    float depth = 0.0; // optical depth along the cone, in units of ln 2
    ivec3 lightVoxel = ivec3(floor(origin + tEnd * dir));
    float tStop = min(tEnd, coneExit(origin, dir, rise, tanHalf, n));
    // depth < 7 / ln 2: transmittance exp(-7) < 1e-3
    for (float t = kConeStart; t < tStop && depth < 10.098865;) {
        float diameter = max(1.0, 2.0 * tanHalf * t);
        vec3 p = origin + t * dir;
        if (any(lessThan(p, vec3(-diameter))) || any(greaterThan(p, vec3(n + diameter))) ||
            ivec3(floor(p)) == lightVoxel)
            break;
        int level = coneLevel(diameter, rise * t / 1.5, f.maxLevel);
        float invSize = exp2Int(-level);
        float stepLength = stepFactor * min(diameter, exp2Int(level));
        // Only the part of the step before the light occludes it.
        depth += sampleDirectional(f, p, level, invSize, false).a * min(stepLength, tEnd - t) * invSize;
        t += stepLength;
    }
    return exp2(-depth);
}

// Direction i of n over the hemisphere around +z, cosine-distributed (Fibonacci spiral): each
// cone then carries the same weight 1/n in the irradiance estimate E / pi = (1/n) sum L_i.
vec3 hemisphereCone(uint i, uint count) {
    float u = (float(i) + 0.5) / float(count);
    float r = sqrt(u);
    float phi = float(i) * 2.39996323; // golden angle: spreads the spiral evenly
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(1.0 - u, 0.0)));
}

mat3 tangentFrame(vec3 n) {
    vec3 t = abs(n.z) < 0.999 ? normalize(cross(vec3(0.0, 0.0, 1.0), n)) : vec3(1.0, 0.0, 0.0);
    return mat3(t, cross(n, t), n);
}

// Defines NAME(origin, normal, cp, extra, turn, out occlusion): (1/n) sum over the diffuse cones
// of their radiance and the mean AO occlusion, each cone traced by TRACE (traceCone's signature;
// `extra` is its last float: the grid size for traceCone, the start for the clipmap's tracer).
// The cone set turns about the normal by `turn` radians (rotated cone sets, vct_trace_body.glsl).
// A macro because GLSL has no function parameters: one gather serves the grid and the clipmap.
// The per-pixel trace defines VCT_SKIPPED_CONE(origin, d, normal), a statement that ends a cone
// whose skipped segment meets a surface, with that surface's light (vct_trace_body.glsl); the
// voxels' own gathers start from above their voxels' surfaces and skip nothing.
#ifndef VCT_SKIPPED_CONE
#define VCT_SKIPPED_CONE(origin, d, normal)
#endif
#define VCT_DEFINE_DIFFUSE_GATHER(NAME, TRACE)                                                   \
    vec3 NAME(vec3 origin, vec3 normal, ConeParams cp, float extra, float turn,                  \
              out float occlusion) {                                                             \
        mat3 frame = tangentFrame(normal);                                                       \
        frame[0] = cos(turn) * frame[0] + sin(turn) * frame[1];                                  \
        frame[1] = cross(normal, frame[0]);                                                      \
        vec3 sum = vec3(0.0);                                                                    \
        occlusion = 0.0;                                                                         \
        uint count = cp.info.x;                                                                  \
        for (uint i = 0u; i < count; ++i) {                                                      \
            float occ;                                                                           \
            vec3 d = frame * hemisphereCone(i, count);                                           \
            VCT_SKIPPED_CONE(origin, d, normal)                                                  \
            sum += TRACE(origin, d, dot(d, normal), cp.cone.x, cp.cone.y, cp.cone.z, extra, occ).rgb; \
            occlusion += occ;                                                                    \
        }                                                                                        \
        occlusion /= float(count);                                                               \
        return sum / float(count);                                                               \
    }

VCT_DEFINE_DIFFUSE_GATHER(diffuseGather, traceCone)
