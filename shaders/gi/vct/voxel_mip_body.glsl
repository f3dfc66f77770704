// One level of the directional volume's mips (Crassin's pre-integration): each output voxel
// covers 2x2x2 source voxels; for each of the six viewing directions the two source voxels
// along that direction are composited front to back (premultiplied, c = c_f + (1 - a_f) c_b),
// then the four resulting columns are averaged, each from the same direction's tile one level
// finer (level 0: the voxels' own views). The six directions are stacks of layers of one 2D
// array image, addressed by vctDirectionalTexel (vct_passes.h). With GI_VOXEL_MIP_LIST (level 1 only, voxel_mip_list.comp) one
// invocation per listed occupied 2^3 block: a block without occupied voxels has only empty
// level-0 texels (the list pass's clear zeroes level 0 and every writer of level 0 writes listed
// voxels only), so its level-1 texels are 0, which the same clear wrote; ~10% of the blocks are
// occupied, and level 1 reads the whole 6 N^3 level 0 in the dense dispatch.
#extension GL_EXT_control_flow_attributes : require
#include "gi/vct_passes.h"

#ifdef GI_VOXEL_MIP_TAIL
// The coarsest levels in one work group (voxel_mip_tail.comp): level info.x (info.y <= 8 texels
// a side) from `src`, then each next one from the previous, info.z levels in all (<= 4). The
// levels are read back within the group after a barrier, where separate passes would each pay
// a dispatch and a pipeline barrier for a few hundred texels.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#elif defined(GI_VOXEL_MIP_LIST)
layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // indirect: the block quad of the list header
layout(set = 1, binding = VCT_MIP_BINDING_LIST, std430) readonly buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint entries[]; };
#else
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#endif
layout(push_constant) uniform Push { VoxelMipPush pc; };
layout(set = 1, binding = VCT_MIP_BINDING_SOURCE, rgba16f) uniform readonly image2DArray src; // level - 1
#ifdef GI_VOXEL_MIP_JOBS
layout(set = 1, binding = VCT_MIP_BINDING_NORMAL, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = VCT_MIP_BINDING_JOBS, std430) buffer Jobs { uint jobHeader[GI_BOUNCE_HEADER]; uint words[]; };
layout(set = 1, binding = VCT_MIP_BINDING_FACES, r32ui) uniform readonly uimage3D facesVol;
#define VOXEL_BLOCK_FACES
#include "voxel_block.glsl"

// Second bounce, job list (gi/vct_passes.h; the clear wrote the header's constant words and
// zeroed the counts and every block's class mask): the classes of the block's voxels' normals
// (voxel_block.glsl) join its bounce block's mask, and the invocation that sets a class's bit
// first appends the (bounce block, class) job to that class's list. The order within a list
// follows the scheduling; each gather depends only on its block and class and stores its result
// at them, so the images do not. (This pass already reads the listed blocks' voxels, which a
// pass of its own over the 4^3 blocks would read again.)
// It also adds the voxels to their (bounce block, class)'s sums, which spare most gathers their
// loops over the block's voxels (voxel_bounce.comp).
// The sums of the voxels of one class in a bounce block (gi/vct_passes.h) gain those of
// `count` voxels: integer adds and maxima, so they do not depend on the order. The largest
// dot(c, normal) uses `first`, the normal of one of them: it is read only when every voxel of
// the class stores the same normal.
void addSums(uint record, uint count, uvec3 offsets, uint largest, uint smallest, uint highest) {
    atomicAdd(words[record], count | (offsets.x << 10u));
    atomicAdd(words[record + 1u], offsets.y | (offsets.z << 16u));
    atomicMax(words[record + 2u], largest);
    atomicMax(words[record + 3u], ~smallest);
    atomicMax(words[record + 4u], highest);
}

void appendJobs(ivec3 c, uint n) {
    uint side = n / bounceBlockSide(n);
    uvec3 q = uvec3(2 * c) / bounceBlockSide(n);
    // A bounce block whose voxels and neighbour blocks (the apply interpolates between them) all
    // lie in the kept box gathers nothing: those voxels keep their second bounce.
    int s = int(bounceBlockSide(n));
    ivec3 near0 = max(ivec3(q) * s - s, ivec3(0)), near1 = min(ivec3(q) * s + 2 * s - 1, ivec3(n - 1u));
    if (all(greaterThanEqual(near0, pc.keepLo.xyz)) && all(lessThanEqual(near1, pc.keepHi.xyz)))
        return;
    uint b = q.x + side * (q.y + side * q.z);
    uint records = bounceGeometryOffset(n) + GI_BOUNCE_GEOMETRY * GI_BOUNCE_CLASSES * b;
    uvec3 origin = q * bounceBlockSide(n);
    // The eight voxels; the class of the first with a normal gathers the others of its class
    // (usually all) into one set of sums, any other voxel adds its own.
    bool has[8];
    uint classes[8], bytes[8];
    uint mask = 0u, first = ~0u, firstBytes = 0u;
    [[unroll]] for (int i = 0; i < 8; ++i) {
        vec3 normal;
        ivec3 v;
        has[i] = voxelNormalOf(2 * c + ivec3(i & 1, (i >> 1) & 1, i >> 2), normal, classes[i], v);
        bytes[i] = voxelNormalBytes(v);
        if (has[i]) {
            mask |= 1u << classes[i];
            if (first == ~0u) {
                first = classes[i];
                firstBytes = bytes[i];
            }
        }
    }
    // The sides of the voxels without a normal (voxelSides) join their classes one by one, and
    // the block's mask (appended below).
    [[unroll]] for (int i = 0; i < 8; ++i) {
        ivec3 p = 2 * c + ivec3(i & 1, (i >> 1) & 1, i >> 2);
        for (uint sides = has[i] ? 0u : voxelSides(p); sides != 0u; sides &= sides - 1u) {
            uint d = uint(findLSB(sides));
            ivec3 v = voxelSideInt(d);
            uint k = voxelNormalClass(v), b8 = voxelNormalBytes(v);
            mask |= 1u << k;
            addSums(records + GI_BOUNCE_GEOMETRY * k, 1u, uvec3(p) - origin, b8, b8,
                    orderedFromFloat(dot(vec3(p), voxelNormalFromBytes(b8))));
        }
    }
    if (mask == 0u)
        return;
    if (first != ~0u) { // not sides only
        vec3 firstNormal = voxelNormalFromBytes(firstBytes);
        uint count = 0u, largest = 0u, smallest = ~0u, highest = 0u;
        uvec3 offsets = uvec3(0u);
        [[unroll]] for (int i = 0; i < 8; ++i) {
            ivec3 p = 2 * c + ivec3(i & 1, (i >> 1) & 1, i >> 2);
            if (has[i] && classes[i] == first) {
                count += 1u;
                offsets += uvec3(p) - origin;
                largest = max(largest, bytes[i]);
                smallest = min(smallest, bytes[i]);
                highest = max(highest, orderedFromFloat(dot(vec3(p), firstNormal)));
            }
        }
        // Neighbouring listed blocks mostly share their bounce block and class: one set of atomics
        // per subgroup and record (integer sums: the same result).
        uint record = records + GI_BOUNCE_GEOMETRY * first;
        for (;;) {
            uint leader = subgroupBroadcastFirst(record);
            if (record == leader) {
                uint packed0 = subgroupAdd(count | (offsets.x << 10u));
                uint packed1 = subgroupAdd(offsets.y | (offsets.z << 16u));
                largest = subgroupMax(largest);
                smallest = subgroupMin(smallest);
                highest = subgroupMax(highest);
                if (subgroupElect()) {
                    atomicAdd(words[record], packed0);
                    atomicAdd(words[record + 1u], packed1);
                    atomicMax(words[record + 2u], largest);
                    atomicMax(words[record + 3u], ~smallest);
                    atomicMax(words[record + 4u], highest);
                }
                break;
            }
        }
        [[unroll]] for (int i = 0; i < 8; ++i) {
            ivec3 p = 2 * c + ivec3(i & 1, (i >> 1) & 1, i >> 2);
            if (has[i] && classes[i] != first)
                addSums(records + GI_BOUNCE_GEOMETRY * classes[i], 1u, uvec3(p) - origin, bytes[i], bytes[i],
                        orderedFromFloat(dot(vec3(p), voxelNormalFromBytes(bytes[i]))));
        }
    }
    uint fresh = mask & ~atomicOr(words[b], mask);
    while (fresh != 0u) {
        uint k = uint(findLSB(fresh));
        fresh &= fresh - 1u;
        uint slot = atomicAdd(jobHeader[GI_BOUNCE_COUNTS + k], 1u);
        if (slot % GI_VOXEL_LIST_GROUP == 0u) // x = ceil(largest count / group)
            atomicMax(jobHeader[0], slot / GI_VOXEL_LIST_GROUP + 1u);
        words[bounceJobOffset(n) + k * bounceBlockCount(n) + slot] = b;
    }
}
#endif

#ifdef GI_VOXEL_MIP_TAIL
// Levels info.x .. info.x + 3 (those past the last are bound to the last and not touched).
layout(set = 1, binding = VCT_MIP_BINDING_TAIL + 0, rgba16f) uniform coherent image2DArray tail0;
layout(set = 1, binding = VCT_MIP_BINDING_TAIL + 1, rgba16f) uniform coherent image2DArray tail1;
layout(set = 1, binding = VCT_MIP_BINDING_TAIL + 2, rgba16f) uniform coherent image2DArray tail2;
layout(set = 1, binding = VCT_MIP_BINDING_TAIL + 3, rgba16f) uniform coherent image2DArray tail3;
#else
layout(set = 1, binding = VCT_MIP_BINDING_TARGET, rgba16f) uniform writeonly image2DArray dst; // level
#endif

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

// t := the 2x2x2 block at `base` of view d of image IMG (the level below).
#define GI_MIP_GATHER(IMG, base, d, n, t)                                                              \
    [[unroll]] for (int i = 0; i < 8; ++i)                                                            \
        t[i] = imageLoad(IMG, vctDirectionalTexel((base) + ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1), d, n));

// Texel c of every view of image DST from image SRC one level finer. Unrolled (with integrate):
// every array index is a constant, so llvmpipe keeps the eight texels in registers instead of a
// dynamically indexed array in memory.
#define GI_MIP_TEXEL(SRC, DST, c, n)                                                                   \
    [[unroll]] for (int d = 0; d < 6; ++d) {                                                          \
        vec4 t[8];                                                                                     \
        GI_MIP_GATHER(SRC, 2 * (c), uint(d), n, t)                                                     \
        imageStore(DST, vctDirectionalTexel(c, uint(d), n), integrate(t, d >> 1, (d & 1) == 0));          \
    }

#ifdef GI_VOXEL_MIP_TAIL
// One level of the tail (`size` texels a side), then the group waits until it is stored.
#define GI_MIP_TAIL_LEVEL(SRC, DST, size)                                                              \
    if (all(lessThan(c, ivec3(size)))) {                                                               \
        GI_MIP_TEXEL(SRC, DST, c, n)                                                                   \
    }                                                                                                  \
    memoryBarrierImage();                                                                              \
    barrier();

void main() {
    uint n = pc.grid.dims.x;
    int size = int(pc.info.y), levels = int(pc.info.z);
    ivec3 c = ivec3(gl_LocalInvocationID);
    GI_MIP_TAIL_LEVEL(src, tail0, size)
    if (levels > 1) {
        GI_MIP_TAIL_LEVEL(tail0, tail1, size >> 1)
    }
    if (levels > 2) {
        GI_MIP_TAIL_LEVEL(tail1, tail2, size >> 2)
    }
    if (levels > 3) {
        GI_MIP_TAIL_LEVEL(tail2, tail3, size >> 3)
    }
}
#else
void main() {
    int size = int(pc.info.y);
    uint n = pc.grid.dims.x;
#ifdef GI_VOXEL_MIP_LIST
    if (gl_GlobalInvocationID.x >= header[GI_VOXEL_LIST_BLOCKS + 3u])
        return;
    ivec3 c = ivec3(voxelListUnpack(entries[n * n * n + gl_GlobalInvocationID.x]));
#ifdef GI_VOXEL_MIP_JOBS
    appendJobs(c, n);
#endif
#else
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(c, ivec3(size))))
        return;
#endif
    GI_MIP_TEXEL(src, dst, c, n)
}
#endif
