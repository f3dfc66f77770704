// GLSL only: the low-resolution gather with discontinuity refinement shared by the VPL and the
// VCT passes. Low-res texel li holds the value computed at full-res pixel lowResSource(li);
// every full-res pixel interpolates the 4 nearest low-res texels bilinearly unless one of them
// (with non-zero weight) lies across a discontinuity: background, normals differing by more
// than the threshold (1 - dot), or a sample off the pixel's tangent plane by more than
// threshold x depth. Such pixels go to a refine list and are recomputed at full resolution.
// The includer declares sampler2D gPosition and gNormal (the G-buffer, point-sampled), or
// declares them as storage images and defines GI_LOWRES_GBUFFER_FETCH(image, pixel) as
// imageLoad(image, pixel) (lavapipe loads storage texels much faster than it fetches through a
// sampler), or defines GI_LOWRES_SOURCE_ONLY to get lowResSource alone.
#ifndef VKGI_GI_LOWRES_UPSAMPLE_H
#define VKGI_GI_LOWRES_UPSAMPLE_H

// Full-res pixel a low-res texel stands for (factor f, full-res size `full`).
ivec2 lowResSource(ivec2 li, int f, ivec2 full) { return min(li * f + f / 2, full - 1); }

#ifndef GI_LOWRES_SOURCE_ONLY // the gather side needs no G-buffer samplers
#ifndef GI_LOWRES_GBUFFER_FETCH
#define GI_LOWRES_GBUFFER_FETCH(image, pixel) texelFetch(image, pixel, 0)
#endif

// Bilinear taps of full-res pixel px (position, normal n, distance to the camera `depth`) on
// the low-res grid of size `low`; true when one of them crosses a discontinuity.
bool lowResTaps(ivec2 px, vec3 position, vec3 n, float depth, int f, ivec2 low, ivec2 full, float threshold,
                out ivec2 taps[4], out vec4 weights) {
    vec2 c = (vec2(px) - float(f / 2)) / float(f);
    ivec2 i0 = ivec2(floor(c));
    vec2 t = c - vec2(i0);
    bool refine = false;
    for (int k = 0; k < 4; ++k) {
        ivec2 o = ivec2(k & 1, k >> 1);
        float w = (o.x == 1 ? t.x : 1.0 - t.x) * (o.y == 1 ? t.y : 1.0 - t.y);
        ivec2 li = clamp(i0 + o, ivec2(0), low - 1);
        taps[k] = li;
        weights[k] = w;
        if (w <= 0.0)
            continue;
        ivec2 s = lowResSource(li, f, full);
        vec4 q = GI_LOWRES_GBUFFER_FETCH(gPosition, s);
        vec3 nq = GI_LOWRES_GBUFFER_FETCH(gNormal, s).xyz;
        if (q.w == 0.0 || 1.0 - dot(n, nq) > threshold || abs(dot(q.xyz - position.xyz, n)) > threshold * depth)
            refine = true;
    }
    return refine;
}

// Joint bilateral variant of lowResTaps (the VCT upsample) for the pixels lowResTaps would
// refine. Where every tap with a non-zero weight passes lowResTaps' test the result is its
// bilinear interpolation. Otherwise the pixel is next to an edge; it is refined when it lies
// behind, or less than `reach` voxels in front of, the surface of a tap that fails the test (a
// surface seen past an edge, or a concave corner: the cones' first samples reach `reach` voxels,
// so there the gather changes faster than the taps sample it). Else only the taps on its own
// surface at the scale of the voxel grid stand in for it: normal within the threshold, off its
// tangent plane by at most half a voxel, and at most `reach` voxels away (across a grazing plane
// neighbouring taps can be metres apart). They are interpolated with their bilinear weights,
// renormalised; where those weights are all zero (the pixel lies on the line through the
// rejected taps, the kept ones one low-res spacing away) they count equally. A pixel that keeps
// no tap is refined too. `voxel` is the voxel edge in the units of the positions.
//
// lowResTapCell gives the taps (low-res texels i0 + (k & 1, k >> 1)) and the bilinear weights;
// lowResFitTapsAt decides from the taps' G-buffer samples (q = position, nq = normal), which
// the caller loads once for all pixels with the same taps (at f = 4 a 4x4 block of pixels);
// lowResTapsEdge is its first half (whether the pixel is next to an edge).
void lowResTapCell(ivec2 px, int f, ivec2 low, out ivec2 taps[4], out vec4 weights) {
    vec2 c = (vec2(px) - float(f / 2)) / float(f);
    ivec2 i0 = ivec2(floor(c));
    vec2 t = c - vec2(i0);
    for (int k = 0; k < 4; ++k) {
        ivec2 o = ivec2(k & 1, k >> 1);
        weights[k] = (o.x == 1 ? t.x : 1.0 - t.x) * (o.y == 1 ? t.y : 1.0 - t.y);
        taps[k] = clamp(i0 + o, ivec2(0), low - 1);
    }
}

// Per tap: its distance off the pixel's tangent plane (off) and whether it passes lowResTaps'
// test (fits); true when a tap with a non-zero weight fails it (the pixel is next to an edge).
bool lowResTapsEdge(vec3 position, vec3 n, float depth, float threshold, vec4 q[4], vec3 nq[4], vec4 weights,
                    out vec4 off, out bvec4 fits) {
    bool edge = false;
    for (int k = 0; k < 4; ++k) {
        off[k] = abs(dot(q[k].xyz - position.xyz, n));
        fits[k] = q[k].w != 0.0 && 1.0 - dot(n, nq[k]) <= threshold && off[k] <= threshold * depth;
        edge = edge || (!fits[k] && weights[k] > 0.0);
    }
    return edge;
}

bool lowResFitTapsAt(vec3 position, vec3 n, float depth, float threshold, float voxel, float reach, vec4 q[4],
                     vec3 nq[4], inout vec4 weights) {
    vec4 off;
    bvec4 fits;
    bool edge = lowResTapsEdge(position, n, depth, threshold, q, nq, weights, off, fits);
    if (!edge) // most pixels: plain bilinear
        return false;
    vec4 keep = vec4(0.0);
    bool near = false;
    for (int k = 0; k < 4; ++k) {
        // A tap that does not fit and whose surface the pixel lies behind (seen past its edge,
        // e.g. through a window or past a column) or less than `reach` voxels in front of (a
        // concave corner, where the gather darkens within the span of the first cone samples):
        // no other tap can stand in for the pixel.
        near = near || (!fits[k] && q[k].w != 0.0 && dot(position.xyz - q[k].xyz, nq[k]) < reach * voxel);
        keep[k] = fits[k] && off[k] <= 0.5 * voxel && distance(q[k].xyz, position.xyz) <= reach * voxel ? 1.0 : 0.0;
    }
    if (near || keep == vec4(0.0))
        return true;
    weights *= keep;
    float sum = dot(weights, vec4(1.0));
    if (sum <= 0.0) {
        weights = keep;
        sum = dot(keep, vec4(1.0));
    }
    weights /= sum;
    return false;
}

#endif

#endif
