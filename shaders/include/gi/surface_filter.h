// GLSL only: one axis of the geometry-aware separable tent filter shared by the VPL interleaved
// gather's reconstruction (gi/vpl_interleave_filter.h) and VCT's filter of the incoming diffuse
// light (vct_filter.comp). The row pass followed by the column pass is the separable tent
// (n - |dx|)(n - |dy|) of side n over the offsets |d| < n, cut where the pixel's surface ends.
//
// The includer defines, before its first call,
//     bool surfaceFilterNeighbour(ivec2 q, vec3 p, vec3 n, float invTolerance)
// : whether pixel q lies inside the image, has geometry, and is on the surface of the pixel at
// p with normal n (surfaceFilterSameSurface on q's own position and normal).
//
// The window [-h, h] is symmetric: it grows one pixel on both sides at a time and stops where
// either side leaves the surface or the image, so a steep change of the light at a contact edge
// (a wall meeting the floor) is not pulled one way. (Letting it grow on one side at the image
// border was worse: there the surface often meets another one just out of view.) Its pixels
// fall into min(2h + 1, n) residue classes (offset mod n) and every class present gets the same
// weight: offset d shares its class with d -+ n when that is inside the window too, and the pair
// then splits the class's weight by the tent, (n - |d|) / n; alone it carries the whole class, 1.
// For a whole window (h = n - 1) this is exactly the tent. With one estimate per class (the VPL
// subsets, or VCT's cone rotations) every estimate the window holds counts equally. The weights
// of each class sum to 1, so the filter of a constant field is that constant.
#ifndef VKGI_GI_SURFACE_FILTER_H
#define VKGI_GI_SURFACE_FILTER_H

// Cosine between normals below which a neighbour is another surface.
const float kSurfaceFilterMinNormalCos = 0.9;

bool surfaceFilterNeighbour(ivec2 q, vec3 p, vec3 n, float invTolerance);

// Whether a neighbour at position q with normal nq lies on the surface of the pixel at p with
// normal n: normals within kSurfaceFilterMinNormalCos and q within the tolerance of p's tangent
// plane (invTolerance = 1 / tolerance in metres).
bool surfaceFilterSameSurface(vec3 p, vec3 n, vec3 q, vec3 nq, float invTolerance) {
    return abs(dot(n, q - p)) * invTolerance <= 1.0 && dot(n, nq) >= kSurfaceFilterMinNormalCos;
}

// Half-width h of pixel px's window along `axis` ((1, 0) or (0, 1)) for a tent of side `side`.
int surfaceFilterHalfWidth(ivec2 px, ivec2 axis, int side, vec3 p, vec3 n, float invTolerance) {
    int h = 0;
    while (h + 1 < side && surfaceFilterNeighbour(px - (h + 1) * axis, p, n, invTolerance) &&
           surfaceFilterNeighbour(px + (h + 1) * axis, p, n, invTolerance))
        ++h;
    return h;
}

// Weight of offset d in a window of half-width h; the weighted sum is divided by
// surfaceFilterClasses(h, side).
float surfaceFilterWeight(int d, int h, int side) {
    int far = side - abs(d); // |offset| of d's class partner
    return far <= h ? float(far) * (1.0 / float(side)) : 1.0;
}

float surfaceFilterClasses(int h, int side) { return float(min(2 * h + 1, side)); }

#endif
