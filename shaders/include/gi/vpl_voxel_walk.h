// GLSL only: a ray's walk through the shared voxel grid's occupancy to the first occupied voxel
// (Amanatides & Woo: every voxel the ray crosses, in order), for the VPL bounce rays
// (vpl_bounce.comp) and the VPL visibility maps (vpl_visibility_map.comp).
//
// The ray starts at o and runs along the unit direction dir, both in grid coordinates (voxel
// units, the grid's box [0, cells]^3); it is clipped to the box first, so a ray from outside
// the grid starts where it enters it. Half voxels (cells twice the volumes' size: the
// camera-centred grid, gi/voxel_grid.h): a half is occupied when its bit in the halves volume's
// alpha is set; otherwise a voxel is occupied when the albedo volume's alpha is.
#ifndef VKGI_GI_VPL_VOXEL_WALK_H
#define VKGI_GI_VPL_VOXEL_WALK_H
#include "voxel_grid.h" // voxelHalfBits

// Orthonormal tangents of unit n (Duff et al. 2017, branchless): a VPL's local frame.
void vplTangentFrame(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

struct VplVoxelHit {
    bool hit;
    float t;  // ray parameter (voxels) where the ray enters the hit voxel
    ivec3 v;  // the hit voxel (in the walk's cells: halves when halved)
    int axis; // the axis of the face the ray entered it through, -1 when it started in it
};

VplVoxelHit vplVoxelWalk(vec3 o, vec3 dir, int cells, sampler3D albedoVolume, sampler3D halvesVolume) {
    VplVoxelHit r = VplVoxelHit(false, 0.0, ivec3(0), -1);
    vec3 inv = 1.0 / dir; // +-inf on axis-parallel rays: the slab test and the steps still work
    vec3 t0 = (vec3(0.0) - o) * inv, t1 = (vec3(float(cells)) - o) * inv;
    float tEnter = max(max(max(min(t0.x, t1.x), min(t0.y, t1.y)), min(t0.z, t1.z)), 0.0);
    float tExit = min(min(max(t0.x, t1.x), max(t0.y, t1.y)), max(t0.z, t1.z));
    if (!(tEnter < tExit))
        return r;
    ivec3 v = clamp(ivec3(floor(o + dir * tEnter)), ivec3(0), ivec3(cells - 1));
    ivec3 stepDir = ivec3(sign(dir));
    vec3 tDelta = abs(inv);
    vec3 tNext = (vec3(v) + max(vec3(stepDir), vec3(0.0)) - o) * inv;
    tNext = mix(tNext, vec3(1e30), equal(stepDir, ivec3(0)));
    float tHit = tEnter;
    int axis = -1;
    int maxSteps = 3 * cells;
    const bool halves = cells > textureSize(albedoVolume, 0).x;
    for (int k = 0; k < maxSteps; ++k) {
        bool occupied;
        if (!halves) {
            occupied = texelFetch(albedoVolume, v, 0).a > 0.5;
        } else {
            uint bits = voxelHalfBits(texelFetch(halvesVolume, v >> 1, 0).a);
            occupied = ((bits >> (uint(v.x & 1) | (uint(v.y & 1) << 1u) | (uint(v.z & 1) << 2u))) & 1u) != 0u;
        }
        if (occupied) {
            r = VplVoxelHit(true, tHit, v, axis);
            break;
        }
        axis = tNext.x < tNext.y ? (tNext.x < tNext.z ? 0 : 2) : (tNext.y < tNext.z ? 1 : 2);
        tHit = tNext[axis];
        v[axis] += stepDir[axis];
        tNext[axis] += tDelta[axis];
        if (v[axis] < 0 || v[axis] >= cells)
            break;
    }
    return r;
}

#endif
