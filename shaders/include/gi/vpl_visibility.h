// GLSL only: the visibility between a receiver and a VPL, marched through the occupancy of the
// shared voxel grid (gi/voxel_grid.h: the albedo volume, a = occupancy) for the gathers with
// vpl.visibility. The includer declares `sampler3D vplOccupancy` and the push block `pc`
// (VplPixelPush: pc.grid = origin and voxel edge, pc.interleave.w = voxels per axis).
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
// emission volume, whose alpha holds each voxel's 2x2x2 half-voxel occupancy bits (gi/voxel_grid.h),
// and pc.grid.w is half the voxel edge: the march (offsets, steps, box) runs on the half voxels,
// as on a grid of twice the resolution, and a sample is blocked when its half's bit is set.
#ifndef VKGI_GI_VPL_VISIBILITY_H
#define VKGI_GI_VPL_VISIBILITY_H

const float kVplVisibilityOffset = 1.5; // voxels: out of the surface's voxel and its conservative neighbour
const float kVplVisibilityStep = 0.75;  // voxels between samples: a one-voxel wall is not stepped over

// Visibility from receiver x (normal nx) to the VPL at p (normal np), in [0, 1].
float vplVisibility(vec3 x, vec3 nx, vec3 p, vec3 np) {
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
                uint bits = uint(texelFetch(vplOccupancy, v >> 1, 0).a + 0.5);
                uint b = uint(v.x & 1) | (uint(v.y & 1) << 1u) | (uint(v.z & 1) << 2u);
                if (((bits >> b) & 1u) != 0u)
                    visibility = 0.0;
            }
        }
    }
    return visibility;
}

#endif
