// Shared body of voxel_resolve.comp and voxel_resolve_merge.comp: fixed-point sums -> means,
// one invocation per voxel of the touched list (indirect dispatch; gi/voxel_passes.h). The
// target volumes hold zeros (resolve: the clear pass zeroed the voxels of the previous list)
// or a copy of the static volumes (merge) beforehand, so the voxels nothing touched need no
// store. Each record read is zeroed, which leaves the whole accumulation zero for the next
// voxelization (every nonzero record is listed). With GI_VOXEL_MERGE, voxels occupied in the
// static volumes keep their static values (Villegas' flag volume: dynamic objects never
// overwrite static voxels).
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
#include "voxel_acc.glsl" // the records (gi/voxel_grid.h), 4 uvec4 each
layout(set = 1, binding = VOXEL_RESOLVE_BINDING_ALBEDO, rgba8) uniform writeonly image3D outAlbedo;
layout(set = 1, binding = VOXEL_RESOLVE_BINDING_NORMAL, rgba8) uniform writeonly image3D outNormal;
layout(set = 1, binding = VOXEL_RESOLVE_BINDING_EMISSION, rgba16f) uniform writeonly image3D outEmission;
layout(set = 1, binding = VOXEL_RESOLVE_BINDING_FACES, r32ui) uniform writeonly uimage3D outFaces;
layout(set = 1, binding = VOXEL_RESOLVE_BINDING_TOUCHED, std430) readonly buffer Touched { uint touchedHeader[GI_VOXEL_TOUCHED_HEADER]; uint touched[]; };
#ifdef GI_VOXEL_MERGE
layout(set = 1, binding = VOXEL_RESOLVE_BINDING_STATIC_ALBEDO, rgba8) uniform readonly image3D staticAlbedo;
#endif

void main() {
    if (gl_GlobalInvocationID.x >= touchedHeader[3])
        return;
    ivec3 c = ivec3(voxelListUnpack(touched[gl_GlobalInvocationID.x]));
    int n = int(pc.grid.dims.x);
    uint slab = voxelAccSlab(c, uint(n));
    uint rec = (GI_VOXEL_ACC_STRIDE / 4u) * voxelAccRecord(c, uint(n));
    // Words 0..12: count and half-voxel bits, albedo rgb, faces +x -x +y -y +z -z, emission rgb
    // (gi/voxel_grid.h).
    uvec4 w0 = voxelAccLoad(slab, rec), w1 = voxelAccLoad(slab, rec + 1u), w2 = voxelAccLoad(slab, rec + 2u),
          w3 = voxelAccLoad(slab, rec + 3u);
    // A voxel listed without a contribution is one a moved clipmap level kept (voxel_mark.comp):
    // its volumes already hold it, and its record is zero.
    if (w0.x == 0u)
        return;
    for (uint k = 0u; k < 4u; ++k)
        voxelAccStore(slab, rec + k, uvec4(0u));
#ifdef GI_VOXEL_MERGE
    if (imageLoad(staticAlbedo, c).a > 0.0)
        return; // the static voxel copied into the target stays
#endif
    uint count = min(w0.x & GI_VOXEL_ACC_COUNT_MASK, GI_VOXEL_MAX_CONTRIBUTIONS);
    float inv = 1.0 / (float(count) * GI_VOXEL_FIXED_ONE);
    vec3 albedo = vec3(w0.yzw) * inv;
    uvec3 p = uvec3(w1.x, w1.z, w2.x), m = uvec3(w1.y, w1.w, w2.y);
    // sum of n_k = sum max(0, n_k) - sum max(0, -n_k)
    vec3 normalSum = vec3(ivec3(p) - ivec3(m));
    vec3 pos = vec3(p) * inv, neg = vec3(m) * inv;
    vec3 emission = vec3(w2.zw, w3.x) * inv * GI_VOXEL_RADIANCE_TARGET;
    // Normals that cancel (both faces of a thin wall) leave no preferred direction: store zero.
    float len = length(normalSum);
    vec3 normal = len > 1e-3 * float(count) * GI_VOXEL_FIXED_ONE ? normalSum / len : vec3(0.0);
    imageStore(outAlbedo, c, vec4(albedo, 1.0));
    // The half-voxel bits (dims.z = 1): a voxel the full test set always has one (a triangle
    // entering it within the test's margin of the halves' faces may pass no half's test: count
    // it whole).
    uint halves = w0.x >> GI_VOXEL_ACC_COUNT_BITS;
    float occupancy = pc.grid.dims.z != 0u ? float(halves != 0u ? halves : 255u) / 255.0 : 1.0;
    imageStore(outNormal, c, vec4(voxelNormalEncode(normal), occupancy));
    float alpha = 0.0;
    // The fill (dims.w = 1): the projected areas P_k (words 13..15, voxel face = 1), each taken
    // once per side: s_k, the larger side's share of axis k's face coverage, is 1 for a sheet
    // and 1/2 for a closed surface, which covers its silhouette from both sides. The axis of the
    // largest P_k s_k counts whole; the others add only their one-sided part, (2 s_k - 1):
    // a closed column's side faces block nothing its front faces do not, but a wall and a floor
    // meeting in the voxel, each covering part of it, bound a closed solid together and add up
    // to an opaque voxel (the edges of a room stay closed to the light outside).
    if (pc.grid.dims.w != 0u) {
        vec3 sides = pos + neg;
        vec3 share = mix(max(pos, neg) / max(sides, vec3(1e-30)), vec3(0.0), equal(sides, vec3(0.0)));
        vec3 blocked = vec3(w3.yzw) * (1.0 / GI_VOXEL_FIXED_ONE) * share;
        int largest = blocked.x >= blocked.y && blocked.x >= blocked.z ? 0 : (blocked.y >= blocked.z ? 1 : 2);
        vec3 weight = 2.0 * share - 1.0;
        weight[largest] = 1.0;
        alpha = min(1.0, max(0.0, dot(blocked, weight)));
    }
    imageStore(outEmission, c, vec4(emission, alpha));
    imageStore(outFaces, c, uvec4(voxelFacesPack(pos, neg)));
}
