// One level of the anisotropic radiance mips (Crassin's pre-integration): each output voxel
// covers 2x2x2 source voxels; for each of the six viewing directions the two source voxels
// along that direction are composited front to back (premultiplied, c = c_f + (1 - a_f) c_b),
// then the four resulting columns are averaged. Level 0 reads the isotropic radiance volume
// (GI_VOXEL_MIP_FROM_RADIANCE), later levels the same direction one level finer.
#include "gi/voxel_passes.h"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(push_constant) uniform Push { VoxelMipPush pc; };
#ifdef GI_VOXEL_MIP_FROM_RADIANCE
layout(set = 1, binding = 0, rgba16f) uniform readonly image3D src;
#else
layout(set = 1, binding = 0, rgba16f) uniform readonly image3D srcPX;
layout(set = 1, binding = 1, rgba16f) uniform readonly image3D srcNX;
layout(set = 1, binding = 2, rgba16f) uniform readonly image3D srcPY;
layout(set = 1, binding = 3, rgba16f) uniform readonly image3D srcNY;
layout(set = 1, binding = 4, rgba16f) uniform readonly image3D srcPZ;
layout(set = 1, binding = 5, rgba16f) uniform readonly image3D srcNZ;
#endif
layout(set = 1, binding = 6, rgba16f) uniform writeonly image3D dstPX;
layout(set = 1, binding = 7, rgba16f) uniform writeonly image3D dstNX;
layout(set = 1, binding = 8, rgba16f) uniform writeonly image3D dstPY;
layout(set = 1, binding = 9, rgba16f) uniform writeonly image3D dstNY;
layout(set = 1, binding = 10, rgba16f) uniform writeonly image3D dstPZ;
layout(set = 1, binding = 11, rgba16f) uniform writeonly image3D dstNZ;

vec4 over(vec4 front, vec4 back) { return front + (1.0 - front.a) * back; }

// Direction `axis` (0..2), positive (the ray travels towards +axis: low coordinate in front).
vec4 integrate(vec4 t[8], int axis, bool positive) {
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 8; ++i) {
        if (((i >> axis) & 1) != 0)
            continue; // i is the low voxel of its column along `axis`
        vec4 lo = t[i], hi = t[i | (1 << axis)];
        sum += positive ? over(lo, hi) : over(hi, lo);
    }
    return 0.25 * sum;
}

vec4[8] gather(ivec3 base, int dir) {
    vec4 t[8];
    for (int i = 0; i < 8; ++i) {
        ivec3 q = base + ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1);
#ifdef GI_VOXEL_MIP_FROM_RADIANCE
        t[i] = imageLoad(src, q);
#else
        switch (dir) {
        case 0: t[i] = imageLoad(srcPX, q); break;
        case 1: t[i] = imageLoad(srcNX, q); break;
        case 2: t[i] = imageLoad(srcPY, q); break;
        case 3: t[i] = imageLoad(srcNY, q); break;
        case 4: t[i] = imageLoad(srcPZ, q); break;
        default: t[i] = imageLoad(srcNZ, q); break;
        }
#endif
    }
    return t;
}

void main() {
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(c, ivec3(pc.info.y))))
        return;
    ivec3 base = 2 * c;
#ifdef GI_VOXEL_MIP_FROM_RADIANCE
    vec4 t[8] = gather(base, 0);
    imageStore(dstPX, c, integrate(t, 0, true));
    imageStore(dstNX, c, integrate(t, 0, false));
    imageStore(dstPY, c, integrate(t, 1, true));
    imageStore(dstNY, c, integrate(t, 1, false));
    imageStore(dstPZ, c, integrate(t, 2, true));
    imageStore(dstNZ, c, integrate(t, 2, false));
#else
    imageStore(dstPX, c, integrate(gather(base, 0), 0, true));
    imageStore(dstNX, c, integrate(gather(base, 1), 0, false));
    imageStore(dstPY, c, integrate(gather(base, 2), 1, true));
    imageStore(dstNY, c, integrate(gather(base, 3), 1, false));
    imageStore(dstPZ, c, integrate(gather(base, 4), 2, true));
    imageStore(dstNZ, c, integrate(gather(base, 5), 2, false));
#endif
}
