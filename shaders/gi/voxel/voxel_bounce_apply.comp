#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce, apply half: each occupied voxel with a normal gets albedo * E / pi, with
// E / pi = (1/n) sum L_i from the gather of its 4^3 block and normal class (voxel_bounce.comp),
// interpolated between neighbouring blocks (below). The misfits' own
// gathers (voxel_bounce_misfits.comp) overwrite theirs afterwards. The result goes to the
// bounce volume; voxel_bounce_add.comp adds it to the level-0 views of the voxel's normal side,
// so the per-pixel gather then sees emission + one bounce + two bounces.
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // one invocation per occupied voxel (indirect)
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = 0, rgba8) uniform readonly image3D albedoVol;
layout(set = 1, binding = 1, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = 2, std430) readonly buffer Jobs { uint header[GI_BOUNCE_HEADER]; uint words[]; };
layout(set = 1, binding = 3, rgba16f) uniform writeonly image3D bounceOut;
layout(set = 1, binding = 4, std430) readonly buffer List { uint listHeader[GI_VOXEL_LIST_HEADER]; uint entries[]; };
layout(set = 1, binding = 5, std430) readonly buffer Results { uint results[]; };
#include "voxel_block.glsl"

void main() {
    if (gl_GlobalInvocationID.x >= listHeader[3])
        return;
    uint n = pc.grid.dims.x, side = n / bounceBlockSide(n);
    ivec3 c = ivec3(voxelListUnpack(entries[gl_GlobalInvocationID.x]));
    vec3 normal;
    uint k;
    if (!voxelNormalOf(c, normal, k)) {
        imageStore(bounceOut, c, vec4(0.0)); // no hemisphere: no second bounce
        return;
    }
    // Bilinear (linear for an edge class, none for a corner) over the gathers of class k at
    // the centres of the nearest blocks along the axes the class direction lies across, i.e.
    // along the surface, never across it (a floor under a table top takes nothing of the top's
    // gather). Blocks without class k are left out and the weights renormalised; the voxel's
    // own block always weighs at least 5/8 per axis. Fixed order: deterministic.
    uint kk = k < 13u ? k : k + 1u;
    bvec3 along = equal(ivec3(kk % 3u, (kk / 3u) % 3u, kk / 9u), ivec3(1)); // class direction component 0
    vec3 f = (vec3(c) + 0.5) / float(bounceBlockSide(n)) - 0.5;
    ivec3 own = c / int(bounceBlockSide(n));
    ivec3 base = mix(own, ivec3(floor(f)), along);
    vec3 w = mix(vec3(0.0), f - floor(f), along);
    vec3 e = vec3(0.0);
    float weights = 0.0;
    for (int i = 0; i < 8; ++i) {
        ivec3 corner = ivec3(i & 1, (i >> 1) & 1, i >> 2);
        vec3 cw = mix(1.0 - w, w, vec3(corner));
        float weight = cw.x * cw.y * cw.z;
        ivec3 q = base + corner;
        if (weight == 0.0 || any(lessThan(q, ivec3(0))) || any(greaterThanEqual(q, ivec3(side))))
            continue;
        uint b = uint(q.x) + side * (uint(q.y) + side * uint(q.z));
        if ((words[b] & (1u << k)) == 0u)
            continue;
        uint r = 2u * (GI_BOUNCE_CLASSES * b + k);
        e += weight * vec3(unpackHalf2x16(results[r]), unpackHalf2x16(results[r + 1u]).x);
        weights += weight;
    }
    e /= weights;
    imageStore(bounceOut, c, vec4(imageLoad(albedoVol, c).rgb * e, 1.0));
}
