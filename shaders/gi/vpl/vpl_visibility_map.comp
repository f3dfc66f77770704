#version 460
#extension GL_GOOGLE_include_directive : require
// The VPLs' visibility maps (gi/vpl_visibility.h): one thread per VPL and texel walks the texel's
// ray from the VPL's origin (kVplVisibilityOffset voxels off its surface) through the voxel
// grid's occupancy and writes how far it got (metres), or kVplVisibilityUnblocked. Empty records
// get kVplVisibilityUnblocked (their light is 0).
#include "gi/vpl.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_1D) in;
layout(push_constant) uniform PushBlock { VplBouncePush pc; };

layout(set = 1, binding = VPL_VISIBILITY_MAP_BINDING_VPLS, std430) readonly buffer Vpls { VplRecord vpls[]; };
layout(set = 1, binding = VPL_VISIBILITY_MAP_BINDING_ALBEDO) uniform sampler3D albedoVolume;
layout(set = 1, binding = VPL_VISIBILITY_MAP_BINDING_HALVES) uniform sampler3D halvesVolume;
layout(set = 1, binding = VPL_VISIBILITY_MAP_BINDING_MAP, std430) writeonly buffer Map { float vplVisibilityMap[]; };

#include "gi/vpl_visibility.h"

void main() {
    const uint texels = GI_VPL_VISIBILITY_MAP_SIDE * GI_VPL_VISIBILITY_MAP_SIDE;
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.info.x * texels)
        return;
    uint k = i / texels, texel = i % texels;
    VplRecord v = vpls[k];
    float reach = kVplVisibilityUnblocked;
    if (v.position.w > 0.0) {
        vec3 n = v.direction.xyz;
        vec3 t, b;
        vplTangentFrame(n, t, b);
        ivec2 c = ivec2(texel % GI_VPL_VISIBILITY_MAP_SIDE, texel / GI_VPL_VISIBILITY_MAP_SIDE);
        vec3 l = vplVisibilityTexelDirection(c);
        vec3 dir = normalize(t * l.x + b * l.y + n * l.z);
        float voxel = pc.origin.w;
        vec3 o = (v.position.xyz + n * (kVplVisibilityOffset * voxel) - pc.origin.xyz) / voxel;
        VplVoxelHit walk = vplVoxelWalk(o, dir, int(pc.grid.y), albedoVolume, halvesVolume);
        if (walk.hit)
            reach = walk.t * voxel;
    }
    vplVisibilityMap[i] = reach;
}
