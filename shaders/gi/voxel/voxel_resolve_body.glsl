// Shared body of voxel_resolve.comp and voxel_resolve_merge.comp: fixed-point sums -> means.
// With GI_VOXEL_MERGE, voxels occupied in the static volumes keep their static values
// (Villegas' flag volume: dynamic objects never overwrite static voxels).
#include "gi/voxel_passes.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 4) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = 0, r32ui) uniform readonly uimage3D accum;
layout(set = 1, binding = 1, rgba8) uniform writeonly image3D outAlbedo;
layout(set = 1, binding = 2, rgba8) uniform writeonly image3D outNormal;
layout(set = 1, binding = 3, rgba16f) uniform writeonly image3D outEmission;
layout(set = 1, binding = 4, r32ui) uniform writeonly uimage3D outFaces;
#ifdef GI_VOXEL_MERGE
layout(set = 1, binding = 5, rgba8) uniform readonly image3D staticAlbedo;
layout(set = 1, binding = 6, rgba8) uniform readonly image3D staticNormal;
layout(set = 1, binding = 7, rgba16f) uniform readonly image3D staticEmission;
layout(set = 1, binding = 8, r32ui) uniform readonly uimage3D staticFaces;
#endif

uint acc(ivec3 c, int channel) { return imageLoad(accum, c + ivec3(0, 0, int(pc.grid.dims.x) * channel)).x; }

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(c, ivec3(pc.grid.dims.x))))
        return;
#ifdef GI_VOXEL_MERGE
    vec4 sa = imageLoad(staticAlbedo, c);
    if (sa.a > 0.0) {
        imageStore(outAlbedo, c, sa);
        imageStore(outNormal, c, imageLoad(staticNormal, c));
        imageStore(outEmission, c, imageLoad(staticEmission, c));
        imageStore(outFaces, c, imageLoad(staticFaces, c));
        return;
    }
#endif
    uint count = min(acc(c, GI_VOXEL_ACC_COUNT), GI_VOXEL_MAX_CONTRIBUTIONS);
    if (count == 0u) {
        imageStore(outAlbedo, c, vec4(0.0));
        imageStore(outNormal, c, vec4(0.0));
        imageStore(outEmission, c, vec4(0.0));
        imageStore(outFaces, c, uvec4(0u));
        return;
    }
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
