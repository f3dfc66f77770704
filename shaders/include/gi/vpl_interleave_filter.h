// GLSL only: one axis of the interleaved gather's reconstruction, shared by the row and column
// passes. The includer declares the push block `pc` (VplPixelPush), the G-buffer samplers
// gPosition and gNormal, and the samplers filterIncident and filterTravel it filters.
//
// Each pixel of the gather image holds one of the n^2 VPL subsets, scaled by n^2. A tent of
// half-width n, w(d) = n - |d|, gives every residue d mod n the same total weight n, so the row
// pass followed by the column pass (a separable tent, (n - |dx|)(n - |dy|)) weighs every subset
// equally: on a surface that fills the window the result is the mean of the n^2 subset
// estimates, i.e. the full gather, smoothed over the tile. A neighbour on another surface
// (normals apart, or off this pixel's tangent plane by more than a fraction of the distance to
// the camera) gets no weight; irradiance is filtered, the albedo is applied per pixel after.
#ifndef VKGI_GI_VPL_INTERLEAVE_FILTER_H
#define VKGI_GI_VPL_INTERLEAVE_FILTER_H
#include "vpl.h"

// Cosine between normals below which a neighbour is another surface.
const float kVplFilterMinNormalCos = 0.9;

ivec2 vplGbufferSample(ivec2 p) {
    int f = int(pc.size.z);
    return min(p * f + f / 2, ivec2(pc.counts.zw) - 1);
}

// Filters pixel px along `axis` ((1, 0) or (0, 1)); returns its G-buffer position (w > 0 where
// there is geometry) and the filtered irradiance and travel directions (zero without geometry).
// `withTravel` (uniform): the travel directions are filtered too (the negative VPLs read them).
vec4 vplInterleaveFilter(ivec2 px, ivec2 axis, bool withTravel, out vec3 e, out vec3 travel) {
    e = vec3(0.0);
    travel = vec3(0.0);
    vec4 position = texelFetch(gPosition, vplGbufferSample(px), 0);
    if (position.w <= 0.0)
        return position;
    vec3 n = texelFetch(gNormal, vplGbufferSample(px), 0).xyz;
    float invTolerance = 1.0 / max(pc.params.z * distance(position.xyz, pc.camera.xyz), 1e-30);
    int side = int(pc.interleave.x);
    ivec2 size = ivec2(pc.size.xy);
    float weightSum = 0.0;
    for (int d = 1 - side; d < side; ++d) {
        ivec2 q = px + d * axis;
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size)))
            continue;
        ivec2 qs = vplGbufferSample(q);
        vec4 qp = texelFetch(gPosition, qs, 0);
        float planeOffset = abs(dot(n, qp.xyz - position.xyz)) * invTolerance;
        if (qp.w <= 0.0 || planeOffset > 1.0 || dot(n, texelFetch(gNormal, qs, 0).xyz) < kVplFilterMinNormalCos)
            continue;
        float w = float(side - abs(d));
        weightSum += w;
        e += w * texelFetch(filterIncident, q, 0).rgb;
        if (withTravel)
            travel += w * texelFetch(filterTravel, q, 0).xyz;
    }
    // The pixel itself always passes, so weightSum >= n.
    e /= weightSum;
    travel /= weightSum;
    return position;
}

#endif
