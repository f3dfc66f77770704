#version 460
// LPV injection, optional pass 0 (LpvSettings::rsmReduce = F > 1): the RSM reduced by F per axis
// before injection and the geometry volume, which then read F^2 fewer texels (their cost is
// reading the RSM: docs/lpv.md). Each output texel is one surfel standing for the valid texels
// of an F x F block: flux summed (energy exactly conserved), position the flux-weighted mean, and
// normal the flux-weighted mean of the unit normals, not renormalised: cosineLobe is linear in n,
// so (sum F_i / pi) cosineLobe(n_mean) is the sum of the texels' lobes when all channels carry
// the same weights (inject.comp keeps normals shorter than 1 as they are). Weights are the sum of
// the 3 flux channels; a block without flux weights its valid texels equally. w = 1 where the
// block has a valid texel, 0 elsewhere. Bad texels are skipped as inject.comp skips them.
//
// A block is merged only where one surfel can stand for it: its valid texels within an RMS
// distance of pc.params.y (half the finest LPV cell) of their mean plane, and the mean of their
// unit normals at least 1/2 long. A block across a depth discontinuity (a roof's edge over the ground beside a
// wall) or a sharp corner would put its light where none of its texels are, e.g. inside the
// building; such a block gets w = 2 and the injection and the geometry volume read its texels
// one by one from the full RSM (LPV_REDUCE_SPLIT).
#extension GL_GOOGLE_include_directive : require
#include "gi/lpv_passes.h"

layout(local_size_x = 8, local_size_y = 8) in;
// The factor, specialised (2 or 4): a constant trip count lets the block loop unroll.
layout(constant_id = LPV_REDUCE_SPEC_FACTOR) const int kFactor = 2;
layout(push_constant) uniform PushBlock { LpvInjectPush pc; }; // rsm: source texels per row, layers, F, output texels per row
// Storage images, not samplers: on lavapipe imageLoad is cheaper than texelFetch through a sampler.
layout(set = 1, binding = LPV_INJECT_BINDING_POSITION, rgba32f) uniform readonly image2DArray rsmPosition;
layout(set = 1, binding = LPV_INJECT_BINDING_NORMAL, rgba16f) uniform readonly image2DArray rsmNormal;
layout(set = 1, binding = LPV_INJECT_BINDING_FLUX, rgba32f) uniform readonly image2DArray rsmFlux;
layout(set = 1, binding = LPV_REDUCE_BINDING_POSITION, rgba32f) uniform writeonly image2DArray outPosition;
layout(set = 1, binding = LPV_REDUCE_BINDING_NORMAL, rgba16f) uniform writeonly image2DArray outNormal;
layout(set = 1, binding = LPV_REDUCE_BINDING_FLUX, rgba32f) uniform writeonly image2DArray outFlux;

void main() {
    ivec3 o = ivec3(gl_GlobalInvocationID);
    if (o.x >= pc.rsm.w || o.y >= pc.rsm.w || o.z >= pc.rsm.y)
        return;
    const int f = kFactor;
    float weight = 0.0, count = 0.0;
    vec3 flux = vec3(0.0), wp = vec3(0.0), wn = vec3(0.0), p = vec3(0.0), n = vec3(0.0);
    // Second moments of the valid texels' positions about the first one (small numbers: no
    // cancellation far from the origin), for their spread across the block's mean plane.
    vec3 origin = vec3(0.0), d1 = vec3(0.0), d2 = vec3(0.0), dx = vec3(0.0); // dx: (xy, xz, yz)
    for (int y = 0; y < f; ++y)
        for (int x = 0; x < f; ++x) {
            ivec3 t = ivec3(o.xy * f + ivec2(x, y), o.z);
            if (t.x >= pc.rsm.x || t.y >= pc.rsm.x)
                continue;
            vec4 tp = imageLoad(rsmPosition, t);
            vec3 tn = imageLoad(rsmNormal, t).xyz;
            vec3 tf = imageLoad(rsmFlux, t).rgb;
            float nn = dot(tn, tn);
            if (!(tp.w > 0.0) || !(nn > 1e-12 && nn < 1e30) || !(abs(tf.r) + abs(tf.g) + abs(tf.b) < 1e30) ||
                !(abs(tp.x) + abs(tp.y) + abs(tp.z) < 1e30))
                continue;
            tn *= inversesqrt(nn);
            float w = max(tf.r + tf.g + tf.b, 0.0);
            flux += tf;
            weight += w;
            wp += w * tp.xyz;
            wn += w * tn;
            count += 1.0;
            p += tp.xyz;
            n += tn;
            if (count == 1.0)
                origin = tp.xyz;
            vec3 d = tp.xyz - origin;
            d1 += d;
            d2 += d * d;
            dx += vec3(d.x * d.y, d.x * d.z, d.y * d.z);
        }
    bool byFlux = weight > 0.0;
    float inv = byFlux ? 1.0 / weight : 1.0 / max(count, 1.0);
    vec3 mean = (byFlux ? wp : p) * inv;
    vec3 meanNormal = (byFlux ? wn : n) * inv;
    // Does the merged surfel stand for every texel? Its light is injected at the merged position,
    // inside the texels' convex hull, so merging cannot carry light across a wall unless the
    // texels lie on different levels: a roof's edge and the ground beside the building. Those
    // spread across the block's mean plane: split when the RMS distance from it exceeds the merge
    // radius (half a cell: less moves no texel's light out of the cell it would reach anyway). A
    // mean of unit normals shorter than 1/2 is a fold so sharp that the lobes mostly cancel and
    // the offset along the mean normal points nowhere in particular.
    float radius = pc.params.y;
    bool split = false;
    float nl = dot(n, n);
    if (radius > 0.0 && count > 1.0) {
        vec3 u = nl > 1e-12 ? n * inversesqrt(nl) : vec3(0.0);
        vec3 m1 = d1 / count;
        float second = dot(u * u, d2 / count) + 2.0 * dot(vec3(u.x * u.y, u.x * u.z, u.y * u.z), dx / count);
        float variance = second - dot(u, m1) * dot(u, m1);
        split = variance > radius * radius || nl < 0.25 * count * count;
    }
    float w = count > 0.0 ? (split ? LPV_REDUCE_SPLIT : 1.0) : 0.0;
    imageStore(outPosition, o, vec4(mean, w));
    imageStore(outNormal, o, vec4(meanNormal, 0.0));
    imageStore(outFlux, o, vec4(flux, 0.0));
}
