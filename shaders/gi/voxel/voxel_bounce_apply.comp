#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce, apply half: each occupied voxel with a normal gets albedo * E / pi, with
// E / pi = (1/n) sum L_i from its block's gather (voxel_bounce.comp) when its normal is within
// kBlockFit of the block's mean normal, else from its own gather (edges, corners, thin walls
// whose faces share a block). The result goes to the bounce volume; voxel_bounce_add.comp adds
// it to the level-0 views of the voxel's normal side, so the per-pixel gather then sees
// emission + one bounce + two bounces.
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // one invocation per occupied voxel (indirect)
layout(push_constant) uniform Push { VoxelBouncePush pc; };
#include "voxel_cone.glsl"
layout(set = 1, binding = 2, rgba8) uniform readonly image3D albedoVol;
layout(set = 1, binding = 3, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = 4, rgba16f) uniform readonly image3D gathered; // (N/2)^3
layout(set = 1, binding = 5, rgba16f) uniform writeonly image3D bounceOut;
layout(set = 1, binding = 6, std430) readonly buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint entries[]; };
#include "voxel_block.glsl"

// cos 25 degrees. Tilting a hemisphere by theta swaps (1 - cos theta) / 2 of its cosine-
// weighted directions for others (4.7% at 25 degrees, within the 6-14% the cones lose at
// coarse levels, docs/vct.md); flat and gently curved surfaces use the block, edges and
// corners (45 or 90 degrees, 15% or 50%) their own gather.
const float kBlockFit = 0.906;

void main() {
    if (gl_GlobalInvocationID.x >= header[3])
        return;
    ivec3 c = ivec3(voxelListUnpack(entries[gl_GlobalInvocationID.x]));
    vec3 normal = voxelNormalDecode(imageLoad(normalVol, c).xyz);
    if (dot(normal, normal) < 0.25) {
        // Normals that cancel: no hemisphere to gather over (no second bounce).
        imageStore(bounceOut, c, vec4(0.0));
        return;
    }
    normal = normalize(normal);
    vec3 e;
    if (dot(normal, blockNormal(c >> 1)) >= kBlockFit) {
        e = imageLoad(gathered, c >> 1).rgb;
    } else {
        float occlusion;
        e = diffuseGather(vec3(c) + 0.5 + normal, normal, pc.cones, float(pc.grid.dims.x), occlusion);
    }
    vec3 albedo = imageLoad(albedoVol, c).rgb;
    imageStore(bounceOut, c, vec4(albedo * e, 1.0));
}
