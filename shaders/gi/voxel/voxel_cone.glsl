// Cone tracing through the voxel radiance (Crassin et al. 2011). The includer declares nothing
// at bindings 0..1; binding 1 is the directional volume (a 2D array: per viewing direction a
// stack of slices across its axis, level 0 the voxels themselves, level k the 2^k-voxel blocks;
// voxel_passes.h). Everything is in grid units (voxels); radiance stays scaled by radianceScale.
layout(set = 1, binding = 1) uniform sampler2DArray aniso;

// Cones start this far (voxels) from their origin, which callers already offset by one voxel
// along the normal: together they clear the surface's own (conservatively thick) voxel.
const float kConeStart = 1.0;
// Accumulated opacity at which a cone stops (the rest would add under 1%).
const float kConeOpaque = 0.99;

// Smallest transmittance 1 - a a stored opacity can express: the largest half float below 1 is
// 1 - 2^-11, so an opaque texel reads as optical depth ln(2^11) ~ 7.6 (transmittance 5e-4).
const float kMinTransmit = 1.0 / 2048.0;

// Optical depth of one texel seen along an axis, from its stored opacity.
float opticalDepth(float a) {
    return -log(max(1.0 - a, kMinTransmit));
}

// Directional sample of level `lod` of the directional volume: rgb = radiance (not
// premultiplied) of what the sample holds, a = optical depth per texel width along `dir`.
// The voxels are surfaces, i.e. sheets: a path of unit length along dir crosses the sheets
// perpendicular to axis k |dir_k| times as often as a path along k does, so the optical depths
// of the three views facing dir add with weights |dir_k| (Crassin's dir^2 blend of the
// opacities instead gives a floor crossed at 45 degrees the opacity of half its face-on view
// plus half its edge-on view, which thins out level by level: the closed box lost 25-30% of
// its opacity at 64^3, more the finer the grid, i.e. the coarser the level its walls are
// reached at). The radiance is the mean of the views' radiances weighted by what each
// contributes to the extinction, so an opaque face-on view hides the edge-on views behind it.
// Stacks are picked by arithmetic, not by branching, so SIMD lanes with different directions
// still take one path (three fetches instead of up to six).
vec4 sampleAniso(vec3 uvw, vec3 dir, float lod, bool ahead) {
    float n = float(textureSize(aniso, 0).x); // N: layers per view at every level
    float texels = n * exp2(-lod);            // this level's resolution
    vec3 w = abs(dir);
    vec3 stack = (vec3(0.0, 2.0, 4.0) + step(dir, vec3(0.0))) * n; // first layer of +X,-X,+Y,-Y,+Z,-Z
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
    vec3 q = uvw * texels; // in texels of this level
    vec3 slice = floor(q);
    if (ahead && lod >= 0.5)
        slice = mix(floor(q + 0.5) - 1.0, ceil(q - 0.5), step(0.0, dir));
    // Beyond the grid every view is empty. Along a view's axis a slice outside [0, texels)
    // (whose layer would belong to another slice or view) weighs 0. Across it the sampler
    // clamps to the edge (lavapipe filters ~8% faster than with a border colour) and `edge`
    // restores the transparent border exactly: within half a texel of the grid's face the
    // bilinear taps are the edge texel and one beyond it, which the border makes 0, i.e. the
    // clamped value times the edge texel's weight q + 0.5 (texels + 0.5 - q at the far face);
    // inside the grid the factor is 1.
    vec3 inside = step(vec3(0.0), slice) * step(slice, vec3(texels - 1.0));
    vec3 edge = clamp(q + 0.5, 0.0, 1.0) * clamp(texels + 0.5 - q, 0.0, 1.0);
    vec3 layer = stack + clamp(slice, vec3(0.0), vec3(texels - 1.0));
    vec4 sx = (inside.x * edge.y * edge.z) * textureLod(aniso, vec3(uvw.yz, layer.x), lod);
    vec4 sy = (inside.y * edge.x * edge.z) * textureLod(aniso, vec3(uvw.xz, layer.y), lod);
    vec4 sz = (inside.z * edge.x * edge.y) * textureLod(aniso, vec3(uvw.xy, layer.z), lod);
    vec3 tau = w * vec3(opticalDepth(sx.a), opticalDepth(sy.a), opticalDepth(sz.a));
    float depth = tau.x + tau.y + tau.z;
    // radiance of view k = rgb_k / a_k (premultiplied); weights tau_k / depth
    vec3 radiance = tau.x * sx.rgb / max(sx.a, 1e-6) + tau.y * sy.rgb / max(sy.a, 1e-6) + tau.z * sz.rgb / max(sz.a, 1e-6);
    return vec4(depth > 0.0 ? radiance / depth : vec3(0.0), depth);
}

// Sample of mip level `level` (a footprint 2^level voxels wide; level 0 = the voxels' own
// views). One level per sample (the sampler's mip mode is NEAREST): blending two levels
// doubles the texels a sample reads, and the cone accounts for the footprint it actually got
// (traceCone). Returns rgb = radiance, a = optical depth per texel width along dir.
vec4 sampleVoxels(vec3 p, vec3 dir, float level, float n, bool ahead) {
    return sampleAniso(p / n, dir, level, ahead);
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
    vec4 acc = vec4(0.0);
    occlusion = 0.0;
    float maxLod = log2(n);
    float tMax = 1.7321 * n; // the grid diagonal
    for (float t = kConeStart; t < tMax && acc.a < kConeOpaque;) {
        float diameter = max(1.0, 2.0 * tanHalf * t);
        vec3 p = origin + t * dir;
        if (any(lessThan(p, vec3(-diameter))) || any(greaterThan(p, vec3(n + diameter))))
            break;
        float level = min(min(round(log2(diameter)), floor(log2(max(rise * t / 1.5, 1.0)))), maxLod);
        float stepLength = stepFactor * min(diameter, exp2(level));
        vec4 s = sampleVoxels(p, dir, level, n, true);
        float a = 1.0 - exp(-s.a * stepLength * exp2(-level));
        acc += (1.0 - acc.a) * vec4(s.rgb * a, a);
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
    float maxLod = log2(n);
    float depth = 0.0; // optical depth along the cone
    ivec3 lightVoxel = ivec3(floor(origin + tEnd * dir));
    for (float t = kConeStart; t < tEnd && depth < 7.0;) { // exp(-7) < 1e-3
        float diameter = max(1.0, 2.0 * tanHalf * t);
        vec3 p = origin + t * dir;
        if (any(lessThan(p, vec3(-diameter))) || any(greaterThan(p, vec3(n + diameter))) ||
            ivec3(floor(p)) == lightVoxel)
            break;
        float level = min(min(round(log2(diameter)), floor(log2(max(rise * t / 1.5, 1.0)))), maxLod);
        float stepLength = stepFactor * min(diameter, exp2(level));
        // Only the part of the step before the light occludes it.
        depth += sampleVoxels(p, dir, level, n, false).a * min(stepLength, tEnd - t) * exp2(-level);
        t += stepLength;
    }
    return exp(-depth);
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

// (1/n) sum over the diffuse cones of their radiance, and the mean AO occlusion.
vec3 diffuseGather(vec3 origin, vec3 normal, ConeParams cp, float n, out float occlusion) {
    mat3 frame = tangentFrame(normal);
    vec3 sum = vec3(0.0);
    occlusion = 0.0;
    uint count = cp.info.x;
    for (uint i = 0u; i < count; ++i) {
        float occ;
        vec3 d = frame * hemisphereCone(i, count);
        sum += traceCone(origin, d, dot(d, normal), cp.cone.x, cp.cone.y, cp.cone.z, n, occ).rgb;
        occlusion += occ;
    }
    occlusion /= float(count);
    return sum / float(count);
}
