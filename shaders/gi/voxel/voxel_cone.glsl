// Cone tracing through the voxel radiance (Crassin et al. 2011). The includer declares nothing
// at bindings 0..1: the isotropic radiance volume and the packed anisotropic volume (six
// direction tiles stacked along z, voxel_passes.h). Everything is in grid units (voxels);
// radiance stays scaled by radianceScale.
layout(set = 1, binding = 0) uniform sampler3D radianceVol;
layout(set = 1, binding = 1) uniform sampler3D aniso;

// Cones start this far (voxels) from their origin, which callers already offset by one voxel
// along the normal: together they clear the surface's own (conservatively thick) voxel.
const float kConeStart = 1.0;
// Accumulated opacity at which a cone stops (the rest would add under 1%).
const float kConeOpaque = 0.99;

// Directional sample: the three direction tiles facing `dir`, weighted by dir^2 (sums to 1).
// Tiles are picked by arithmetic, not by branching, so SIMD lanes with different directions
// still take one path (three fetches instead of up to six). Along z the coordinate is clamped
// half a texel of the coarser of the two levels inside the tile, so filtering never reads the
// neighbouring tile; beyond the grid in z the sample is empty, as the border is in x and y.
vec4 sampleAniso(vec3 uvw, vec3 dir, float lod) {
    if (uvw.z < 0.0 || uvw.z > 1.0)
        return vec4(0.0);
    float levels = float(textureQueryLevels(aniso));
    float tileTexels = float(textureSize(aniso, 0).x) / exp2(min(ceil(lod), levels - 1.0));
    float z = clamp(uvw.z, 0.5 / tileTexels, 1.0 - 0.5 / tileTexels);
    vec3 w = dir * dir;
    vec3 tile = vec3(0.0, 2.0, 4.0) + step(dir, vec3(0.0)); // +X,-X,+Y,-Y,+Z,-Z = 0..5
    return w.x * textureLod(aniso, vec3(uvw.xy, (tile.x + z) / 6.0), lod) +
           w.y * textureLod(aniso, vec3(uvw.xy, (tile.y + z) / 6.0), lod) +
           w.z * textureLod(aniso, vec3(uvw.xy, (tile.z + z) / 6.0), lod);
}

// Sample of mip level `level` (a footprint 2^level voxels wide): level 0 is the isotropic
// volume, level 1 + k level k of the anisotropic chains. One level per sample (the sampler's
// mip mode is NEAREST): blending two levels doubles the texels a sample reads, and the cone
// accounts for the footprint it actually got (traceCone).
vec4 sampleVoxels(vec3 p, vec3 dir, float level, float n) {
    vec3 uvw = p / n;
    if (level == 0.0)
        return textureLod(radianceVol, uvw, 0.0);
    return sampleAniso(uvw, dir, level - 1.0);
}

// Front-to-back accumulation along a cone of half-angle atan(tanHalf). Samples are spaced
// stepFactor diameters apart. Each reads the mip level nearest to the cone's diameter d,
// whose pre-integrated voxels stand for slabs 2^level thick; the opacity is corrected from
// that slab to the step length s = stepFactor * d: a' = 1 - (1 - a)^(s / 2^level) (colour
// likewise, premultiplied). With d = 2^level this is the plain a' = 1 - (1 - a)^stepFactor.
// `occlusion` gets Villegas' AO: opacity weighted by 1 / (1 + decay * distance).
vec4 traceCone(vec3 origin, vec3 dir, float tanHalf, float stepFactor, float decay, float n, out float occlusion) {
    vec4 acc = vec4(0.0);
    occlusion = 0.0;
    float maxLod = log2(n);
    float tMax = 1.7321 * n; // the grid diagonal
    for (float t = kConeStart; t < tMax && acc.a < kConeOpaque;) {
        float diameter = max(1.0, 2.0 * tanHalf * t);
        vec3 p = origin + t * dir;
        if (any(lessThan(p, vec3(-diameter))) || any(greaterThan(p, vec3(n + diameter))))
            break;
        float level = min(round(log2(diameter)), maxLod);
        float stepLength = stepFactor * diameter;
        vec4 s = sampleVoxels(p, dir, level, n);
        float a = 1.0 - pow(max(1.0 - s.a, 0.0), stepLength * exp2(-level));
        s.rgb *= s.a > 1e-6 ? a / s.a : 0.0;
        acc += (1.0 - acc.a) * vec4(s.rgb, a);
        occlusion += (1.0 - occlusion) * a / (1.0 + decay * t);
        t += stepLength;
    }
    return acc;
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
        sum += traceCone(origin, frame * hemisphereCone(i, count), cp.cone.x, cp.cone.y, cp.cone.z, n, occ).rgb;
        occlusion += occ;
    }
    occlusion /= float(count);
    return sum / float(count);
}
