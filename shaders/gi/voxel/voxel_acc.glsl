// The accumulation records (gi/voxel_grid.h) as GI_VOXEL_ACC_SLABS storage-buffer ranges of
// whole z-layers at consecutive bindings from VOXEL_ACC_BINDING_RECORDS. The includer defines
// GI_VOXEL_ACC_WORDS (uint words, atomics: voxelize.comp) or neither (uvec4 loads and stores:
// the resolves). Below 256^3 the records fit in the first range: the specialization constant
// kVoxelAccSlabs is false (VoxelGrid::create), the compiler drops the switch, and only the
// first binding is read (the others alias it). With slabs a switch picks the binding; llvmpipe
// runs every case of a switch masked, so only grids that need the slabs pay for the switch.
#ifdef GI_VOXEL_ACC_WORDS
#define GI_VOXEL_ACC_TYPE uint
#else
#define GI_VOXEL_ACC_TYPE uvec4
#endif
layout(set = 1, binding = VOXEL_ACC_BINDING_RECORDS + 0, std430) buffer Accum0 { GI_VOXEL_ACC_TYPE acc0[]; };
layout(set = 1, binding = VOXEL_ACC_BINDING_RECORDS + 1, std430) buffer Accum1 { GI_VOXEL_ACC_TYPE acc1[]; };
layout(set = 1, binding = VOXEL_ACC_BINDING_RECORDS + 2, std430) buffer Accum2 { GI_VOXEL_ACC_TYPE acc2[]; };
layout(set = 1, binding = VOXEL_ACC_BINDING_RECORDS + 3, std430) buffer Accum3 { GI_VOXEL_ACC_TYPE acc3[]; };
layout(set = 1, binding = VOXEL_ACC_BINDING_RECORDS + 4, std430) buffer Accum4 { GI_VOXEL_ACC_TYPE acc4[]; };
layout(set = 1, binding = VOXEL_ACC_BINDING_RECORDS + 5, std430) buffer Accum5 { GI_VOXEL_ACC_TYPE acc5[]; };
layout(set = 1, binding = VOXEL_ACC_BINDING_RECORDS + 6, std430) buffer Accum6 { GI_VOXEL_ACC_TYPE acc6[]; };
layout(set = 1, binding = VOXEL_ACC_BINDING_RECORDS + 7, std430) buffer Accum7 { GI_VOXEL_ACC_TYPE acc7[]; };

layout(constant_id = 0) const bool kVoxelAccSlabs = false; // voxelAccSlabLayers(N) < N

// Slab of voxel c and the index of its record within the slab (in records); layer counts are
// powers of two.
uint voxelAccSlab(ivec3 c, uint n) { return kVoxelAccSlabs ? uint(c.z) >> findMSB(voxelAccSlabLayers(n)) : 0u; }
uint voxelAccRecord(ivec3 c, uint n) {
    uint z = kVoxelAccSlabs ? uint(c.z) & (voxelAccSlabLayers(n) - 1u) : uint(c.z);
    return uint(c.x) + n * (uint(c.y) + n * z);
}

#ifdef GI_VOXEL_ACC_WORDS
// One atomic on the record word of slab `slab`: the slabs are separate bindings, and GLSL cannot
// pass a buffer, so each atomic gets its switch from this macro.
#define GI_VOXEL_ACC_ATOMIC(NAME, ATOMIC)                                  \
    uint NAME(uint slab, uint word, uint value) {                          \
        if (!kVoxelAccSlabs)                                               \
            return ATOMIC(acc0[word], value);                              \
        switch (slab) {                                                    \
        case 0u: return ATOMIC(acc0[word], value);                         \
        case 1u: return ATOMIC(acc1[word], value);                         \
        case 2u: return ATOMIC(acc2[word], value);                         \
        case 3u: return ATOMIC(acc3[word], value);                         \
        case 4u: return ATOMIC(acc4[word], value);                         \
        case 5u: return ATOMIC(acc5[word], value);                         \
        case 6u: return ATOMIC(acc6[word], value);                         \
        default: return ATOMIC(acc7[word], value);                         \
        }                                                                  \
    }
GI_VOXEL_ACC_ATOMIC(voxelAccAdd, atomicAdd)
GI_VOXEL_ACC_ATOMIC(voxelAccOr, atomicOr)
#else
uvec4 voxelAccLoad(uint slab, uint i) {
    if (!kVoxelAccSlabs)
        return acc0[i];
    switch (slab) {
    case 0u: return acc0[i];
    case 1u: return acc1[i];
    case 2u: return acc2[i];
    case 3u: return acc3[i];
    case 4u: return acc4[i];
    case 5u: return acc5[i];
    case 6u: return acc6[i];
    default: return acc7[i];
    }
}
void voxelAccStore(uint slab, uint i, uvec4 v) {
    if (!kVoxelAccSlabs) {
        acc0[i] = v;
        return;
    }
    switch (slab) {
    case 0u: acc0[i] = v; break;
    case 1u: acc1[i] = v; break;
    case 2u: acc2[i] = v; break;
    case 3u: acc3[i] = v; break;
    case 4u: acc4[i] = v; break;
    case 5u: acc5[i] = v; break;
    case 6u: acc6[i] = v; break;
    default: acc7[i] = v; break;
    }
}
#endif
