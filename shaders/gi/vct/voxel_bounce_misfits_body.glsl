// Second bounce, the misfits (voxel_bounce.comp): voxels whose normal is more than 25 degrees
// from their class's mean gather the diffuse cones over their own hemisphere, from one voxel
// above their centre, and overwrite what the apply (voxel_bounce_apply.comp) wrote for them.
// A compact list of their own, so no SIMD lane waits on another's gather. The clipmap variant
// (voxel_bounce_misfits_clip.comp) gathers through the clipmap volume, as voxel_bounce_clip.comp.
#include "gi/vct_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // one invocation per misfit voxel (indirect)
layout(push_constant) uniform Push { VoxelBouncePush pc; };
#include "voxel_cone.glsl"
#ifdef GI_VCT_CLIPMAP
#include "voxel_clip.glsl"
#endif
layout(set = 1, binding = VCT_MISFITS_BINDING_ALBEDO, rgba8) uniform readonly image3D albedoVol;
layout(set = 1, binding = VCT_MISFITS_BINDING_NORMAL, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = VCT_MISFITS_BINDING_OUTPUT, rgba16f) uniform writeonly image3D bounceOut;
layout(set = 1, binding = VCT_MISFITS_BINDING_JOBS, std430) readonly buffer Jobs { uint header[GI_BOUNCE_HEADER]; uint words[]; };
#include "voxel_block.glsl"

void main() {
    if (gl_GlobalInvocationID.x >= header[GI_BOUNCE_MISFITS + 3u])
        return;
    uint n = pc.grid.dims.x;
    ivec3 c = ivec3(voxelListUnpack(words[bounceMisfitOffset(n) + gl_GlobalInvocationID.x]));
    vec3 normal;
    uint k;
    voxelNormalOf(c, normal, k); // listed by the gather: has a normal
    float occlusion;
#ifdef GI_VCT_CLIPMAP
    vec3 e = clipLevelGather(int(pc.clip.x), vec3(c) + 0.5 + normal, normal, pc.cones, occlusion);
#else
    vec3 e = diffuseGather(vec3(c) + 0.5 + normal, normal, pc.cones, float(n), 0.0, occlusion);
#endif
    imageStore(bounceOut, c, vec4(imageLoad(albedoVol, c).rgb * e, 1.0));
}
