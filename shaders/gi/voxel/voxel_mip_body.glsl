// One level of the anisotropic radiance mips (Crassin's pre-integration): each output voxel
// covers 2x2x2 source voxels; for each of the six viewing directions the two source voxels
// along that direction are composited front to back (premultiplied, c = c_f + (1 - a_f) c_b),
// then the four resulting columns are averaged, each from the same direction's tile one level
// finer (level 0: the voxels' own views). The six directions are stacks of layers of one 2D
// array image, addressed by voxelAnisoTexel (voxel_passes.h). With GI_VOXEL_MIP_LIST (level 1 only, voxel_mip_list.comp) one
// invocation per listed occupied 2^3 block: a block without occupied voxels has only empty
// level-0 texels (the list pass's clear zeroes level 0 and every writer of level 0 writes listed
// voxels only), so its level-1 texels are 0, which the same clear wrote; ~10% of the blocks are
// occupied, and level 1 reads the whole 6 N^3 level 0 in the dense dispatch.
#extension GL_EXT_control_flow_attributes : require
#include "gi/voxel_passes.h"

#ifdef GI_VOXEL_MIP_LIST
layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // indirect: the block quad of the list header
layout(set = 1, binding = 2, std430) readonly buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint entries[]; };
#else
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#endif
layout(push_constant) uniform Push { VoxelMipPush pc; };
layout(set = 1, binding = 0, rgba16f) uniform readonly image2DArray src; // aniso level - 1
layout(set = 1, binding = 1, rgba16f) uniform writeonly image2DArray dst; // aniso level

vec4 over(vec4 front, vec4 back) { return front + (1.0 - front.a) * back; }

// Direction `axis` (0..2), positive (the ray travels towards +axis: low coordinate in front).
vec4 integrate(vec4 t[8], int axis, bool positive) {
    vec4 sum = vec4(0.0);
    [[unroll]] for (int i = 0; i < 8; ++i) {
        if (((i >> axis) & 1) != 0)
            continue; // i is the low voxel of its column along `axis`
        vec4 lo = t[i], hi = t[i | (1 << axis)];
        sum += positive ? over(lo, hi) : over(hi, lo);
    }
    return 0.25 * sum;
}

// The 2x2x2 block at `base` (level - 1) of view d.
vec4[8] gather(ivec3 base, uint d, uint n) {
    vec4 t[8];
    [[unroll]] for (int i = 0; i < 8; ++i)
        t[i] = imageLoad(src, voxelAnisoTexel(base + ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1), d, n));
    return t;
}

void main() {
    int size = int(pc.info.y);
    uint n = pc.grid.dims.x;
#ifdef GI_VOXEL_MIP_LIST
    if (gl_GlobalInvocationID.x >= header[GI_VOXEL_LIST_BLOCKS + 3u])
        return;
    ivec3 c = ivec3(voxelListUnpack(entries[n * n * n + gl_GlobalInvocationID.x]));
#else
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(c, ivec3(size))))
        return;
#endif
    ivec3 base = 2 * c;
    // Unrolled (with the loops above): every array index is a constant, so llvmpipe keeps the
    // eight texels in registers instead of a dynamically indexed array in memory.
    [[unroll]] for (int d = 0; d < 6; ++d)
        imageStore(dst, voxelAnisoTexel(c, uint(d), n), integrate(gather(base, uint(d), n), d >> 1, (d & 1) == 0));
}
