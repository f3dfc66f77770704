#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce, add: each occupied voxel's bounce light B (voxel_bounce_apply.comp, gathered
// over the hemisphere of its mean normal) joins the level-0 views that see faces on that side
// (faces looking towards d with d . normal > 0), weighted as the voxel light weights its own
// radiance there (opacity * shown share, voxel_light_body.glsl), so view texel rgb = a s (L + B).
// Reads and writes only its own voxel's texels: no other invocation touches them.
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // one invocation per occupied voxel (indirect)
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = 0, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = 1, r32ui) uniform readonly uimage3D facesVol;
layout(set = 1, binding = 2, rgba16f) uniform readonly image3D bounce;
layout(set = 1, binding = 3, rgba16f) uniform image2DArray anisoLevel0;
layout(set = 1, binding = 4, std430) readonly buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint entries[]; };

void main() {
    if (gl_GlobalInvocationID.x >= header[3])
        return;
    ivec3 c = ivec3(voxelListUnpack(entries[gl_GlobalInvocationID.x]));
    vec3 b = imageLoad(bounce, c).rgb;
    if (b == vec3(0.0))
        return;
    vec3 normal = voxelNormalDecode(imageLoad(normalVol, c).xyz);
    uint faces = imageLoad(facesVol, c).x;
    uint n = pc.grid.dims.x;
    for (uint v = 0u; v < GI_VOXEL_ANISO_DIRECTIONS; ++v) {
        uint d = v ^ 1u; // the faces a ray travelling along v sees look towards v ^ 1
        float towards = (d & 1u) == 0u ? normal[d >> 1u] : -normal[d >> 1u];
        float front = voxelFaceCoverage(faces, d);
        if (towards <= 0.0 || front == 0.0)
            continue;
        float axisCover = voxelFaceCoverage(faces, 2u * (v >> 1u)) + voxelFaceCoverage(faces, 2u * (v >> 1u) + 1u);
        float shown = min(1.0, 2.0 * front / axisCover);
        ivec3 t = voxelAnisoTexel(c, v, n);
        vec4 texel = imageLoad(anisoLevel0, t);
        texel.rgb = min(texel.rgb + b * (texel.a * shown), vec3(65000.0));
        imageStore(anisoLevel0, t, texel);
    }
}
