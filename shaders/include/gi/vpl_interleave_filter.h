// GLSL only: one axis of the interleaved gather's reconstruction, shared by the row and column
// passes. The includer declares the push block `pc` (VplPixelPush), the gather's packed surfaces
// `usampler2D filterSurface` (gi/vpl_surface.h), and the samplers filterIncident and filterTravel
// it filters.
//
// Each pixel of the gather image holds one of the n^2 VPL subsets, scaled to the whole set
// (by about n^2, vpl_gather.comp), so every subset alone estimates the full gather. A tent of
// half-width n, w(d) = n - |d|, gives every residue d mod n the same total weight n, so the row
// pass followed by the column pass (a separable tent, (n - |dx|)(n - |dy|)) weighs every subset
// equally: on a surface that fills the window the result is the mean of the n^2 subset
// estimates, i.e. the full gather, smoothed over the tile. A neighbour on another surface
// (normals apart, or off this pixel's tangent plane by more than a fraction of the distance to
// the camera) ends the window; a pixel left with at most 3 of the n^2 subsets is gathered
// again in full (vpl_interleave_columns.comp). Irradiance is filtered, the albedo is
// applied per pixel after.
#ifndef VKGI_GI_VPL_INTERLEAVE_FILTER_H
#define VKGI_GI_VPL_INTERLEAVE_FILTER_H
#include "vpl.h"
#include "vpl_surface.h"

// Cosine between normals below which a neighbour is another surface.
const float kVplFilterMinNormalCos = 0.9;

ivec2 vplGbufferSample(ivec2 p) {
    int f = int(pc.size.z);
    return min(p * f + f / 2, ivec2(pc.counts.zw) - 1);
}

// Whether neighbour q lies on the surface of pixel px (position p, normal n): inside the image,
// with geometry, normals within kVplFilterMinNormalCos and on p's tangent plane within the
// tolerance.
bool vplSameSurface(ivec2 q, vec3 p, vec3 n, float invTolerance) {
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(pc.size.xy))))
        return false;
    uvec4 s = texelFetch(filterSurface, q, 0);
    return vplSurfaceValid(s) && abs(dot(n, vplSurfacePosition(s) - p)) * invTolerance <= 1.0 &&
           dot(n, vplSurfaceNormal(s)) >= kVplFilterMinNormalCos;
}

// Filters pixel px along `axis` ((1, 0) or (0, 1)); returns its position (w = 1 where there is
// geometry, else all 0) and the filtered irradiance and travel directions (zero without geometry).
// `withTravel` (uniform): the travel directions are filtered too (the negative VPLs read them).
// `classes` receives the number of subset classes the window covers (n when it is whole).
//
// The window [-h, h] is symmetric: it grows one pixel on both sides at a time and stops where
// either side leaves the surface or the image, so a steep change of the light at a contact edge
// (a wall meeting the floor) is not pulled one way. (Letting it grow on one side at the image
// border was worse: there the surface often meets another one just out of view.) Its pixels
// fall into min(2h + 1, n) residue classes (offset mod n, one subset each), and every class
// present gets the same weight: offset d shares its class with d -+ n when that is inside the
// window too, and the pair then splits the class's weight by the tent, (n - |d|) / n; alone it
// carries the whole class, 1. For a whole window (h = n - 1) this is exactly the tent.
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
    int h = 0;
    while (h + 1 < side && vplSameSurface(px - (h + 1) * axis, position.xyz, n, invTolerance) &&
           vplSameSurface(px + (h + 1) * axis, position.xyz, n, invTolerance))
        ++h;
    float invSide = 1.0 / float(side);
    for (int d = -h; d <= h; ++d) {
        int far = side - abs(d); // |offset| of d's class partner
        float w = far <= h ? float(far) * invSide : 1.0;
        ivec2 q = px + d * axis;
        e += w * texelFetch(filterIncident, q, 0).rgb;
        if (withTravel)
            travel += w * texelFetch(filterTravel, q, 0).xyz;
    }
    classes = float(min(2 * h + 1, side));
    e /= classes;
    travel /= classes;
    return position;
}

#endif
