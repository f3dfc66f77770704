// GLSL only: the visibility between a receiver and a VPL for the gathers with vpl.visibility, in
// one of two ways: marched through the voxel occupancy (VPL_VISIBILITY_MARCH, vpl.visibility on)
// or looked up in the VPL's visibility map (VPL_VISIBILITY_MAPS, vpl.visibility maps).
//
// Both read the push block `pc` (VplPixelPush: pc.grid = the grid's origin and voxel edge,
// pc.interleave.w = voxels per axis).
//
// ---- The march (VPL_VISIBILITY_MARCH). The includer declares `sampler3D vplOccupancy`.
//
// The segment runs between the two points moved kVplVisibilityOffset voxels off their surfaces
// along their normals: the distance to a plane is linear along a segment, so a segment between
// two points that are that far from the receiver's and the VPL's planes stays that far from both
// (their own voxels, and in a corner those of both walls, do not block it). Occluders within the
// offset of either end (contact shadows) are not seen.
//
// The segment is first clipped to the grid's box: the part outside the grid is not tested (no
// occupancy is known there), so a grid centred on the camera in a large world stops light only
// at the occluders within its box, and a segment that misses the box entirely is unoccluded.
// The clipped part is sampled every kVplVisibilityStep voxels or closer: the samples sit at
// i / steps of the whole segment (steps = its length over the step, rounded up), and only the
// indices whose samples can fall inside the box are visited. Their number is bounded by the
// box's diagonal over the step, so no wall inside the grid is ever stepped over, however long
// the segment (a distant sun VPL's), and a segment within the box is sampled exactly as before
// the clipping. The light is multiplied by 1 - occupancy at each sample.
//
// Half voxels: when pc.interleave.w is twice the volume's size, `vplOccupancy` is the grid's
// normal volume, whose alpha holds each voxel's 2x2x2 half-voxel occupancy bits (gi/voxel_grid.h),
// and pc.grid.w is half the voxel edge: the march (offsets, steps, box) runs on the half voxels,
// as on a grid of twice the resolution, and a sample is blocked when its half's bit is set.
//
// ---- The maps (VPL_VISIBILITY_MAPS), and the map texel <-> direction mapping the map pass
// (vpl_visibility_map.comp) shares.
//
// A VPL's map covers the hemisphere about its normal with GI_VPL_VISIBILITY_MAP_SIDE^2 texels
// (hemi-octahedral: the hemisphere's directions projected onto the L1 diamond |x| + |y| <= 1,
// rotated 45 degrees onto the square [-1, 1]^2; texels of nearly equal solid angle). Each texel
// holds how far the ray through its centre travels through the shared voxel grid's occupancy
// (gi/vpl_voxel_walk.h, the walk the bounce rays use) from the VPL's origin, the VPL moved
// kVplVisibilityOffset voxels off its surface along its normal, to the first occupied voxel
// (1e30 when it leaves the grid, or never enters it: nothing is known outside the grid).
//
// A receiver x (normal nx) is tested at the point b moved the same offset off its surface: the
// distance to a plane is linear along a segment, so the segment from the VPL's origin to b stays
// that far from the receiver's and the VPL's planes, and their own voxels do not block it.
// Each of the 4 texels around b's direction gives b's depth along its own ray: where that ray
// meets b's plane (the plane through b with normal nx; "receiver plane depth"), so the texels'
// rays, which pass beside b, are compared at the depth of the same surface, also at grazing
// angles. A texel sees b when its ray reaches that depth less kVplVisibilityTolerance voxels
// before it stops; the visibility is the bilinear blend of the 4 answers. A receiver's own wall
// stops a ray at least one voxel past b's plane (b is 1.5 voxels off it, the conservative
// voxels reach half a voxel out), so a lit plane is not shadowed by itself. Occluders within the
// offset of either end (contact shadows), and those thinner than the map's texels as seen from
// the VPL, are not seen.
//
// Half voxels: on the camera-centred grid (gi/voxel_grid.h) the walk runs on the half voxels and
// the voxel edge is half the volumes' (VplBouncePush::origin.w, VplPixelPush::grid.w).
#ifndef VKGI_GI_VPL_VISIBILITY_H
#define VKGI_GI_VPL_VISIBILITY_H
#include "vpl_voxel_walk.h"

const float kVplVisibilityOffset = 1.5;    // voxels: out of the surface's voxel and its conservative neighbour
const float kVplVisibilityTolerance = 0.5; // voxels a texel's ray may stop short of the receiver's depth
const float kVplVisibilityLateral = 0.5;   // of a tap's lateral offset from b, added to the tolerance
const float kVplVisibilityUnblocked = 1e30;

// Unit direction (local frame, z >= 0) -> [-1, 1]^2.
vec2 vplHemiOctEncode(vec3 l) {
    vec2 p = l.xy / (abs(l.x) + abs(l.y) + max(l.z, 0.0));
    return vec2(p.x + p.y, p.x - p.y);
}

// [-1, 1]^2 -> unit direction (local frame, z >= 0).
vec3 vplHemiOctDecode(vec2 uv) {
    vec2 p = vec2(uv.x + uv.y, uv.x - uv.y) * 0.5;
    return normalize(vec3(p, 1.0 - abs(p.x) - abs(p.y)));
}

// The local direction through the centre of texel c.
vec3 vplVisibilityTexelDirection(ivec2 c) {
    return vplHemiOctDecode((vec2(c) + 0.5) * (2.0 / float(GI_VPL_VISIBILITY_MAP_SIDE)) - 1.0);
}

#ifdef VPL_VISIBILITY_MAPS
// Visibility from receiver x (normal nx) to VPL k at p (normal np), in [0, 1]. The includer
// declares `float vplVisibilityMap[]`.
float vplVisibility(uint k, vec3 x, vec3 nx, vec3 p, vec3 np) {
    float voxel = pc.grid.w;
    vec3 a = p + np * (kVplVisibilityOffset * voxel);
    vec3 b = x + nx * (kVplVisibilityOffset * voxel);
    vec3 d = b - a;
    float len = length(d);
    if (!(len > 0.0))
        return 1.0;
    vec3 t, bt;
    vplTangentFrame(np, t, bt);
    vec3 l = vec3(dot(d, t), dot(d, bt), dot(d, np)) / len;
    const int side = int(GI_VPL_VISIBILITY_MAP_SIDE);
    vec2 f = (vplHemiOctEncode(l) * 0.5 + 0.5) * float(side) - 0.5;
    ivec2 c0 = ivec2(floor(f));
    vec2 w = f - vec2(c0);
    // b's plane in the local frame: a ray u from the origin meets it at dot(d, m) / dot(u, m).
    vec3 m = vec3(dot(nx, t), dot(nx, bt), dot(nx, np));
    float dm = dot(l, m) * len;
    float tolerance = kVplVisibilityTolerance * voxel;
    uint base = k * GI_VPL_VISIBILITY_MAP_SIDE * GI_VPL_VISIBILITY_MAP_SIDE;
    float visibility = 0.0;
    for (int j = 0; j < 4; ++j) {
        ivec2 o = ivec2(j & 1, j >> 1);
        ivec2 c = clamp(c0 + o, ivec2(0), ivec2(side - 1));
        vec3 u = vplVisibilityTexelDirection(c);
        float um = dot(u, m);
        // A texel's ray that does not run towards b's plane is compared at b's own distance.
        float depth = um < -0.05 ? min(dm / um, 2.0 * len) : len;
        float reach = vplVisibilityMap[base + uint(c.y * side + c.x)];
        float weight = (o.x == 1 ? w.x : 1.0 - w.x) * (o.y == 1 ? w.y : 1.0 - w.y);
        // The tap's ray passes len |u - l| beside b: a curved receiver (a concave wall) or a
        // corner may stop it that much short of b's plane.
        float slack = tolerance + kVplVisibilityLateral * len * length(u - l);
        visibility += reach + slack >= depth ? weight : 0.0;
    }
    return visibility;
}
#endif

#ifdef VPL_VISIBILITY_MARCH
const float kVplVisibilityStep = 0.75;  // voxels between samples: a one-voxel wall is not stepped over

// Visibility from receiver x (normal nx) to the VPL k at p (normal np), in [0, 1].
float vplVisibility(uint k, vec3 x, vec3 nx, vec3 p, vec3 np) {
    float voxel = pc.grid.w;
    vec3 a = x + nx * (kVplVisibilityOffset * voxel);
    vec3 b = p + np * (kVplVisibilityOffset * voxel);
    vec3 d = b - a;
    float len = length(d);
    float cellCount = pc.interleave.w;
    // The segment's parameter range [tEnter, tExit] inside the box (slab test; an axis the
    // segment does not move along gets a huge slope instead of 0 / 0).
    vec3 lo = pc.grid.xyz, hi = pc.grid.xyz + vec3(cellCount * voxel);
    vec3 inv = 1.0 / mix(d, vec3(1e-30), equal(d, vec3(0.0)));
    vec3 t0 = (lo - a) * inv, t1 = (hi - a) * inv;
    vec3 tMin = min(t0, t1), tMax = max(t0, t1);
    float tEnter = max(max(max(tMin.x, tMin.y), tMin.z), 0.0);
    float tExit = min(min(min(tMax.x, tMax.y), tMax.z), 1.0);
    if (tEnter > tExit)
        return 1.0;
    // Float, so that a segment to a VPL far outside the grid cannot overflow an int.
    float stepsF = max(ceil(len / (kVplVisibilityStep * voxel)), 1.0);
    vec3 stride = d / stepsF;
    // One index of margin on each side: a sample on the box's face is not lost to rounding (the
    // bounds test below skips those outside).
    int first = int(max(floor(tEnter * stepsF) - 1.0, 0.0));
    int last = int(min(ceil(tExit * stepsF) + 1.0, stepsF));
    // The box's diagonal over the step, plus the margins: never reached by a clipped segment,
    // kept as a bound on the loop.
    int maxSamples = int(ceil(1.7321 * cellCount / kVplVisibilityStep)) + 4;
    last = min(last, first + maxSamples);
    ivec3 cells = ivec3(int(cellCount));
    bool halves = int(cellCount) > textureSize(vplOccupancy, 0).x;
    float invVoxel = 1.0 / voxel;
    float visibility = 1.0;
    for (int i = first; i <= last && visibility > 0.0; ++i) {
        ivec3 v = ivec3(floor((a + float(i) * stride - pc.grid.xyz) * invVoxel));
        if (all(greaterThanEqual(v, ivec3(0))) && all(lessThan(v, cells))) {
            if (!halves) {
                visibility *= 1.0 - texelFetch(vplOccupancy, v, 0).a;
            } else {
                uint bits = voxelHalfBits(texelFetch(vplOccupancy, v >> 1, 0).a);
                uint b = uint(v.x & 1) | (uint(v.y & 1) << 1u) | (uint(v.z & 1) << 2u);
                if (((bits >> b) & 1u) != 0u)
                    visibility = 0.0;
            }
        }
    }
    return visibility;
}

#endif

#endif
