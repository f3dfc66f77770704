// GLSL only: one axis of the interleaved gather's reconstruction, shared by the row and column
// passes. The includer declares the push block `pc` (VplPixelPush), the gather's packed surfaces
// `usampler2D filterSurface` (gi/vpl_surface.h), and the samplers filterIncident and filterTravel
// it filters.
//
// Each pixel of the gather image holds one of the n^2 VPL subsets, scaled to the whole set
// (by about n^2, vpl_gather.comp), so every subset alone estimates the full gather. The shared
// geometry-aware tent of side n (gi/surface_filter.h) gives every residue d mod n the same
// weight, so the row pass followed by the column pass weighs every subset equally: on a surface
// that fills the window the result is the mean of the n^2 subset estimates, i.e. the full
// gather, smoothed over the tile. A neighbour on another surface (normals apart, or off this
// pixel's tangent plane by more than a fraction of the distance to the camera) ends the window;
// a pixel left with at most 3 of the n^2 subsets is gathered again in full
// (vpl_interleave_columns.comp). Irradiance is filtered, the albedo is applied per pixel after.
#ifndef VKGI_GI_VPL_INTERLEAVE_FILTER_H
#define VKGI_GI_VPL_INTERLEAVE_FILTER_H
#include "vpl.h"
#include "vpl_surface.h"
#include "surface_filter.h"

ivec2 vplGbufferSample(ivec2 p) {
    int f = int(pc.size.z);
    return min(p * f + f / 2, ivec2(pc.counts.zw) - 1);
}

// Whether neighbour q lies on the surface of the pixel at p with normal n (gi/surface_filter.h):
// inside the image, with geometry, on that surface.
bool surfaceFilterNeighbour(ivec2 q, vec3 p, vec3 n, float invTolerance) {
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(pc.size.xy))))
        return false;
    uvec4 s = texelFetch(filterSurface, q, 0);
    return vplSurfaceValid(s) &&
           surfaceFilterSameSurface(p, n, vplSurfacePosition(s), vplSurfaceNormal(s), invTolerance);
}

// Filters pixel px along `axis` ((1, 0) or (0, 1)); returns its position (w = 1 where there is
// geometry, else all 0) and the filtered irradiance and travel directions (zero without geometry).
// `withTravel` (uniform): the travel directions are filtered too (the negative VPLs read them).
// `classes` receives the number of subset classes the window covers (n when it is whole).
// The window and weights are the shared filter's (gi/surface_filter.h).
vec4 vplInterleaveFilter(ivec2 px, ivec2 axis, bool withTravel, out vec3 e, out vec3 travel, out float classes) {
    e = vec3(0.0);
    travel = vec3(0.0);
    classes = 0.0;
    uvec4 surface = texelFetch(filterSurface, px, 0);
    if (!vplSurfaceValid(surface))
        return vec4(0.0);
    vec4 position = vec4(vplSurfacePosition(surface), 1.0);
    vec3 n = vplSurfaceNormal(surface);
    float invTolerance = 1.0 / max(pc.params.z * distance(position.xyz, pc.camera.xyz), 1e-30);
    int side = int(pc.interleave.x);
    int h = surfaceFilterHalfWidth(px, axis, side, position.xyz, n, invTolerance);
    for (int d = -h; d <= h; ++d) {
        float w = surfaceFilterWeight(d, h, side);
        ivec2 q = px + d * axis;
        e += w * texelFetch(filterIncident, q, 0).rgb;
        if (withTravel)
            travel += w * texelFetch(filterTravel, q, 0).xyz;
    }
    classes = surfaceFilterClasses(h, side);
    e /= classes;
    travel /= classes;
    return position;
}

#endif
