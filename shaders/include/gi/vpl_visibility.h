// GLSL only: the visibility between a receiver and a VPL, marched through the occupancy of the
// shared voxel grid (gi/voxel_grid.h: the albedo volume, a = occupancy) for the gathers with
// vpl.visibility. The includer declares `sampler3D vplOccupancy` and the push block `pc`
// (VplPixelPush: pc.grid = origin and voxel edge, pc.interleave.w = voxels per axis).
//
// The segment runs between the two points moved kVplVisibilityOffset voxels off their surfaces
// along their normals: the distance to a plane is linear along a segment, so a segment between
// two points that are that far from the receiver's and the VPL's planes stays that far from both
// (their own voxels, and in a corner those of both walls, do not block it). It is sampled every
// kVplVisibilityStep voxels (fewer, evenly spread, when that would take more than
// kVplVisibilityMaxSteps), and the light is multiplied by 1 - occupancy at each sample.
// Occluders within the offset of either end (contact shadows) are not seen.
#ifndef VKGI_GI_VPL_VISIBILITY_H
#define VKGI_GI_VPL_VISIBILITY_H

const float kVplVisibilityOffset = 1.5; // voxels: out of the surface's voxel and its conservative neighbour
const float kVplVisibilityStep = 0.75;  // voxels between samples: a one-voxel wall is not stepped over
const int kVplVisibilityMaxSteps = 64;  // samples per segment at most

// Visibility from receiver x (normal nx) to the VPL at p (normal np), in [0, 1].
float vplVisibility(vec3 x, vec3 nx, vec3 p, vec3 np) {
    float voxel = pc.grid.w;
    vec3 a = x + nx * (kVplVisibilityOffset * voxel);
    vec3 b = p + np * (kVplVisibilityOffset * voxel);
    vec3 d = b - a;
    float len = length(d);
    int steps = clamp(int(ceil(len / (kVplVisibilityStep * voxel))), 1, kVplVisibilityMaxSteps);
    vec3 stride = d / float(steps);
    ivec3 cells = ivec3(int(pc.interleave.w));
    float invVoxel = 1.0 / voxel;
    float visibility = 1.0;
    for (int i = 0; i <= steps && visibility > 0.0; ++i) {
        ivec3 v = ivec3(floor((a + float(i) * stride - pc.grid.xyz) * invVoxel));
        if (all(greaterThanEqual(v, ivec3(0))) && all(lessThan(v, cells)))
            visibility *= 1.0 - texelFetch(vplOccupancy, v, 0).a;
    }
    return visibility;
}

#endif
