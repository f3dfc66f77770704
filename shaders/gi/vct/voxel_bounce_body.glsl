// Second bounce, gather half: one diffuse gather per job, i.e. per (occupied 4^3 block, normal
// class) (voxel_bounce_jobs.comp), over the hemisphere of the class's mean normal m, from the
// class's voxels' centroid lifted along m until it is one voxel above every one of them (as a
// voxel's own gather starts one voxel above its centre, so the first cone sample, 2 voxels
// out, clears the surface). The voxels of a class lie within 30 degrees of its direction and
// in one 4^3 block; the cones are 30 degrees wide and their first sample is already 2 voxels
// across, so the gather changes little over them. The class's voxels whose normal is more than
// kClassFit from m are appended to the misfit list and their misfit bits set (they gather their
// own cones, voxel_bounce_misfits.comp, and the apply takes those; a third bounce's gathers find
// the same misfits and leave the list as the second's made it). Sums run over the block in a
// fixed order: deterministic. voxel_bounce.comp gathers within the grid; voxel_bounce_clip.comp
// (GI_VCT_CLIPMAP) gathers a clipmap level's cones through the clipmap volume, where they go on
// into the coarser levels beyond the level's box (docs/vct.md "Clipmap"). A voxel without a
// normal (its faces' normals cancel: both faces of a thin wall or slab) joins the face class of
// each of its sides (voxelSides) with that axis as its normal, and is never a misfit.
#include "gi/vct_passes.h"

// One invocation per job (indirect): work group row k runs the jobs of class k.
layout(local_size_x = GI_VOXEL_LIST_GROUP) in;
layout(push_constant) uniform Push { VoxelBouncePush pc; };
#include "voxel_cone.glsl"
#ifdef GI_VCT_CLIPMAP
#include "voxel_clip.glsl"
#endif
layout(set = 1, binding = VCT_BOUNCE_BINDING_NORMAL, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = VCT_BOUNCE_BINDING_JOBS, std430) buffer Jobs { uint header[GI_BOUNCE_HEADER]; uint words[]; };
layout(set = 1, binding = VCT_BOUNCE_BINDING_RESULTS, std430) writeonly buffer Results { uint results[]; };
layout(set = 1, binding = VCT_BOUNCE_BINDING_LIST, std430) readonly buffer List { uint listHeader[GI_VOXEL_LIST_HEADER]; uint entries[]; };
layout(set = 1, binding = VCT_BOUNCE_BINDING_FACES, r32ui) uniform readonly uimage3D facesVol;
#define VOXEL_BLOCK_LIST
#define VOXEL_BLOCK_FACES
#include "voxel_block.glsl"

// Whether voxel c gathers with class cls: by its normal's class, or by one of its sides'
// (voxelSides), whose normal is the axis; `side` says which.
bool classMember(ivec3 c, uint cls, out vec3 normal, out bool side) {
    uint k;
    side = false;
    if (voxelNormalOf(c, normal, k))
        return k == cls;
    for (uint sides = voxelSides(c); sides != 0u; sides &= sides - 1u) {
        ivec3 v = voxelSideInt(uint(findLSB(sides)));
        if (voxelNormalClass(v) == cls) {
            normal = voxelNormalFromBytes(voxelNormalBytes(v));
            side = true;
            return true;
        }
    }
    return false;
}

// cos 25 degrees. Tilting a hemisphere by theta swaps (1 - cos theta) / 2 of its cosine-
// weighted directions for others (4.7% at 25 degrees, within the 6-14% the cones lose at
// coarse levels, docs/vct.md); voxels further from their class's mean normal gather their own.
const float kClassFit = 0.906;

void main() {
    uint cls = gl_WorkGroupID.y;
    uint j = gl_GlobalInvocationID.x;
    if (j >= header[GI_BOUNCE_COUNTS + cls])
        return;
    uint n = pc.grid.dims.x, side = n / bounceBlockSide(n);
    int sub = int(bounceBlockSide(n) / 4u);
    uint b = words[bounceJobOffset(n) + cls * bounceBlockCount(n) + j];
    ivec3 q = ivec3(b % side, (b / side) % side, b / (side * side));
    // Over the block's occupied voxels (the list's bits), in a fixed order: the class's centroid
    // and mean normal, then the lift and the misfits. When every voxel of the class stores the
    // same normal (flat axis-aligned or 45-degree surfaces: most jobs) the mean is that normal,
    // nothing misfits and the lift follows from the first pass's largest height along it.
    vec3 sumPosition = vec3(0.0), sumNormal = vec3(0.0), first = vec3(0.0);
    float count = 0.0, highest = -1e30;
    bool same = true;
    // The sums the job listing added (gi/vct_passes.h) when all the class's voxels store the
    // same normal (its largest and smallest normal bytes agree): the values the loop below
    // finds, bit for bit (integer sums below 2^24 are exact in floats in any order).
    uint record = bounceGeometryOffset(n) + GI_BOUNCE_GEOMETRY * (GI_BOUNCE_CLASSES * b + cls);
    bool summed = words[record + 2u] == ~words[record + 3u];
    if (summed) {
        uint counted = words[record] & 1023u;
        uvec3 offsets = uvec3(words[record] >> 10u, words[record + 1u] & 0xFFFFu, words[record + 1u] >> 16u);
        count = float(counted);
        sumPosition = vec3(uvec3(q) * bounceBlockSide(n) * counted + offsets);
        first = voxelNormalFromBytes(words[record + 2u]);
        highest = floatFromOrdered(words[record + 4u]);
    }
    for (int s = 0; s < sub * sub * sub && !summed; ++s) {
        ivec3 q4 = bounceSubBlock(q, s, sub);
        if (!coarseOccupied(q4, n))
            continue;
        for (int row = 0; row < 16; ++row) {
            ivec3 r = 4 * q4 + ivec3(0, row & 3, row >> 2);
            for (uint bits = rowOccupancy(r, n); bits != 0u; bits &= bits - 1u) {
                ivec3 c = r + ivec3(findLSB(bits), 0, 0);
                vec3 normal;
                bool side;
                if (classMember(c, cls, normal, side)) {
                    if (count == 0.0)
                        first = normal;
                    same = same && normal == first;
                    highest = max(highest, dot(vec3(c), first));
                    sumPosition += vec3(c);
                    sumNormal += normal;
                    count += 1.0;
                }
            }
        }
    }
    // The class's normals share its signs within 30 degrees of its direction: no cancelling.
    vec3 mean = same ? first : normalize(sumNormal);
    vec3 middle = sumPosition / count + 0.5;
    float lift = same ? max(highest + 0.5 * (first.x + first.y + first.z) - dot(middle, first), 0.0) : 0.0;
    for (int s = 0; s < sub * sub * sub && !same; ++s) {
        ivec3 q4 = bounceSubBlock(q, s, sub);
        if (!coarseOccupied(q4, n))
            continue;
        for (int row = 0; row < 16; ++row) {
            ivec3 r = 4 * q4 + ivec3(0, row & 3, row >> 2);
            for (uint bits = rowOccupancy(r, n); bits != 0u; bits &= bits - 1u) {
                ivec3 c = r + ivec3(findLSB(bits), 0, 0);
                vec3 normal;
                bool side;
                if (!classMember(c, cls, normal, side))
                    continue;
                lift = max(lift, dot(vec3(c) + 0.5 - middle, mean));
                // A side is an axis, within 30 degrees of its face class's mean: never a misfit.
                if (!side && dot(normal, mean) < kClassFit && pc.clip.y == 0u) {
                    uint slot = atomicAdd(header[GI_BOUNCE_MISFITS + 3u], 1u);
                    if (slot % GI_VOXEL_LIST_GROUP == 0u) // x = ceil(count / group)
                        atomicAdd(header[GI_BOUNCE_MISFITS], 1u);
                    words[bounceMisfitOffset(n) + slot] = voxelListPack(uvec3(c));
                    uvec2 bit = bounceMisfitBit(uvec3(c), n);
                    atomicOr(words[bounceMisfitBitsOffset(n) + bit.x], 1u << bit.y);
                }
            }
        }
    }
    float occlusion;
#ifdef GI_VCT_CLIPMAP
    vec3 gathered = clipLevelGather(int(pc.clip.x), middle + (1.0 + lift) * mean, mean, pc.cones, occlusion);
#else
    vec3 gathered = diffuseGather(middle + (1.0 + lift) * mean, mean, pc.cones, float(n), 0.0, occlusion);
#endif
    uint r = 2u * (GI_BOUNCE_CLASSES * b + cls);
    results[r] = packHalf2x16(gathered.rg);
    results[r + 1u] = packHalf2x16(vec2(gathered.b, 0.0));
}
