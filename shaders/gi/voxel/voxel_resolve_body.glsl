// Shared body of voxel_resolve.comp and voxel_resolve_merge.comp: fixed-point sums -> means,
// one invocation per voxel of the touched list (indirect dispatch; gi/voxel_passes.h). The
// target volumes hold zeros (resolve) or a copy of the static volumes (merge) beforehand, both
// written by transfers, so the voxels nothing touched need no store. With GI_VOXEL_MERGE,
// voxels occupied in the static volumes keep their static values (Villegas' flag volume:
// dynamic objects never overwrite static voxels).
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = 0, r32ui) uniform readonly uimage3D accum;
layout(set = 1, binding = 1, rgba8) uniform writeonly image3D outAlbedo;
layout(set = 1, binding = 2, rgba8) uniform writeonly image3D outNormal;
layout(set = 1, binding = 3, rgba16f) uniform writeonly image3D outEmission;
layout(set = 1, binding = 4, r32ui) uniform writeonly uimage3D outFaces;
layout(set = 1, binding = 9, std430) readonly buffer Touched { uint touchedHeader[GI_VOXEL_TOUCHED_HEADER]; uint touched[]; };
#ifdef GI_VOXEL_MERGE
layout(set = 1, binding = 5, rgba8) uniform readonly image3D staticAlbedo;
#endif

uint acc(ivec3 c, int channel) { return imageLoad(accum, c + ivec3(0, 0, int(pc.grid.dims.x) * channel)).x; }

void main() {
    if (gl_GlobalInvocationID.x >= touchedHeader[3])
        return;
    ivec3 c = ivec3(voxelListUnpack(touched[gl_GlobalInvocationID.x]));
#ifdef GI_VOXEL_MERGE
    if (imageLoad(staticAlbedo, c).a > 0.0)
        return; // the static voxel copied into the target stays
#endif
    uint count = min(acc(c, GI_VOXEL_ACC_COUNT), GI_VOXEL_MAX_CONTRIBUTIONS); // >= 1: it was touched
    float inv = 1.0 / (float(count) * GI_VOXEL_FIXED_ONE);
    vec3 albedo, normalSum, emission, pos, neg;
    for (int k = 0; k < 3; ++k) {
        albedo[k] = float(acc(c, GI_VOXEL_ACC_ALBEDO + k)) * inv;
        uint p = acc(c, GI_VOXEL_ACC_FACES + 2 * k), m = acc(c, GI_VOXEL_ACC_FACES + 2 * k + 1);
        normalSum[k] = float(int(p) - int(m)); // sum of n_k = sum max(0, n_k) - sum max(0, -n_k)
        pos[k] = float(p) * inv;
        neg[k] = float(m) * inv;
        emission[k] = float(acc(c, GI_VOXEL_ACC_EMISSION + k)) * inv * GI_VOXEL_RADIANCE_TARGET;
    }
    // Normals that cancel (both faces of a thin wall) leave no preferred direction: store zero.
    float len = length(normalSum);
    vec3 normal = len > 1e-3 * float(count) * GI_VOXEL_FIXED_ONE ? normalSum / len : vec3(0.0);
    imageStore(outAlbedo, c, vec4(albedo, 1.0));
    imageStore(outNormal, c, vec4(voxelNormalEncode(normal), 1.0));
    imageStore(outEmission, c, vec4(emission, 0.0));
    imageStore(outFaces, c, uvec4(voxelFacesPack(pos, neg)));
}
