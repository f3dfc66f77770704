// Cone tracing through the clipmap (VctSettings::levels > 1, docs/vct.md "Clipmap"), on top of
// voxel_cone.glsl: the binding at VCT_CONE_BINDING_DIRECTIONAL is the clipmap volume (the levels'
// directional volumes stacked along the layers, vct_passes.h). Positions and lengths are in
// finest voxels from level 0's min corner; level l's grid coordinates are (u - level[l].xyz) / 2^l.
layout(set = 1, binding = VCT_TRACE_BINDING_CLIPMAP, std140) uniform ClipmapBlock { VctClipmapParams clip; };

// Width (level voxels) of the band inside a level's faces over which samples fade into the next
// coarser level: a cone crossing a level boundary sees a ramp, not a step (no popping when the
// camera moves the levels).
const float kClipBlend = 4.0;

// The finest level a cone reads: 0 for the per-pixel cones; a clipmap level's second-bounce
// gathers (clipLevelGather) read their own level and, beyond its box, the coarser ones.
int clipFloor = 0;

// Level voxels from u to the nearest face of level l's box.
float clipInset(vec3 u, int l) {
    vec3 q = (u - clip.level[l].xyz) / clip.level[l].w;
    vec3 d = min(q, vec3(float(clip.info.y)) - q);
    return min(min(d.x, d.y), d.z);
}

// The finest level that holds a sample of diameter d (finest voxels) at u with its filter
// footprint inside (twice the diameter in that level's voxels, at least one, plus the texel the
// gathering cones' ahead rule may move on), and the weight of that level against the next
// coarser one (1 away from its faces, falling to 0 across the blend band). The coarsest level
// takes everything else, weight 1.
int clipLevel(vec3 u, float d, out float keep) {
    int levels = int(clip.info.x);
    keep = 1.0;
    for (int k = clipFloor; k < levels - 1; ++k) {
        float need = 2.0 * max(d / clip.level[k].w, 1.0) + 1.0;
        float w = clamp((clipInset(u, k) - need) / kClipBlend, 0.0, 1.0);
        if (w > 0.0) {
            keep = w;
            return k;
        }
    }
    return levels - 1;
}

// Voxel width (finest voxels) of the coarsest level a cone's first samples at surface point u
// read: the cone origins are lifted that far off the surface (one voxel, as on a single grid),
// so that the surface's own, conservatively thick voxels stay behind them.
float clipLift(vec3 u) {
    float keep;
    int l = clipLevel(u, 1.0, keep);
    return clip.level[keep < 1.0 ? l + 1 : l].w;
}

// Sample of level l at u for a cone of diameter d whose filter must stay below `reach` (finest
// voxels; the level cap of traceCone): sampleDirectional's optical depth and depth-weighted
// radiance per finest voxel (so that levels of different voxel sizes blend), and the step this
// texel allows (finest voxels: the diameter, at least the level's voxel, at most the texel).
vec4 clipSample(ConeFrame f, vec3 u, float d, float reach, int l, out float stepWidth) {
    float voxel = clip.level[l].w;
    float inv = 1.0 / voxel; // exact: a power of two
    int mip = coneLevel(max(d * inv, 1.0), reach * inv, f.maxLevel);
    float texel = voxel * exp2Int(mip);
    vec4 s = sampleDirectionalAt(f, (u - clip.level[l].xyz) * inv, mip, exp2Int(-mip), true,
                                 float(GI_VCT_DIRECTIONS * uint(l)) * f.n);
    stepWidth = min(max(d, voxel), texel);
    return s / texel;
}

// The clipmap's sample at u: the finest level holding it, faded into the next coarser one near
// its faces.
vec4 sampleClip(ConeFrame f, vec3 u, float d, float reach, out float stepWidth) {
    float keep;
    // The level follows the texel the sample reads: the diameter, or the largest power of two
    // within `reach` where the level cap is finer (coneLevel). From the diameter alone, the
    // capped samples near a surface went to coarse levels whose voxels reach back to it.
    int l = clipLevel(u, min(d, intBitsToFloat(floatBitsToInt(max(reach, 1.0)) & 0x7F800000)), keep);
    vec4 s = clipSample(f, u, d, reach, l, stepWidth);
    if (keep < 1.0) {
        float coarseStep;
        s = mix(clipSample(f, u, d, reach, l + 1, coarseStep), s, keep);
    }
    return s;
}

// traceCone through the clipmap: the same front-to-back accumulation, level cap and steps, with
// the level of each sample from its position and footprint (Crassin: level from the footprint,
// mip within the level). Starts at `start` (the origin's lift, clipLift) and stops where the
// cone has left the coarsest level for good (coneExit in that level's voxels).
vec4 traceConeClip(vec3 origin, vec3 dir, float rise, float tanHalf, float stepFactor, float decay, float start,
                   out float occlusion) {
    ConeFrame f = coneFrame(dir, float(clip.info.y));
    int top = int(clip.info.x) - 1;
    float topVoxel = clip.level[top].w;
    float tMax = topVoxel * min(1.7321 * f.n, coneExit((origin - clip.level[top].xyz) / topVoxel, dir, rise, tanHalf, f.n));
    vec4 acc = vec4(0.0);
    occlusion = 0.0;
    for (float t = start; t < tMax && acc.a < kConeOpaque;) {
        float diameter = max(clip.level[clipFloor].w, 2.0 * tanHalf * t);
        float stepWidth;
        vec4 s = sampleClip(f, origin + t * dir, diameter, rise * t / 1.5, stepWidth);
        float stepLength = stepFactor * stepWidth;
        float a = 1.0 - exp2(-s.a * stepLength);
        acc.rgb += ((1.0 - acc.a) * (s.a > 0.0 ? a / s.a : 0.0)) * s.rgb;
        acc.a += (1.0 - acc.a) * a;
        occlusion += (1.0 - occlusion) * a / (1.0 + decay * t);
        t += stepLength;
    }
    return acc;
}

// diffuseGather through the clipmap (`extra` = the cones' start).
VCT_DEFINE_DIFFUSE_GATHER(diffuseGatherClip, traceConeClip)

// Level l's diffuse gather from p (level-l voxels, one voxel off the surface, as diffuseGather's
// origin) through the clipmap: the same cones in finest voxels, from one level-l voxel on and at
// least one level-l voxel wide, reading level l and, where their footprint leaves its box, the
// coarser levels (which hold their own second bounce: the levels are lit coarsest first).
vec3 clipLevelGather(int l, vec3 p, vec3 normal, ConeParams cp, out float occlusion) {
    clipFloor = l;
    float voxel = clip.level[l].w;
    return diffuseGatherClip(clip.level[l].xyz + p * voxel, normal, cp, kConeStart * voxel, 0.0, occlusion);
}
