// Shader interface of the voxel-grid passes (C++ and GLSL; the VCT passes: gi/vct_passes.h):
// push constants, the touched-voxel lists and bindings. Each push block stays within
// lavapipe's 128-byte push-constant limit; sizes are pinned on both sides.
#ifndef VKGI_GI_VOXEL_PASSES_H
#define VKGI_GI_VOXEL_PASSES_H
#include "voxel_grid.h"

GI_NAMESPACE_BEGIN

// voxel_resolve*.comp, voxel_touched_list.comp (and VCT passes): the grid only.
GI_GPU_STRUCT(VoxelGridPush) {
    VoxelGridParams grid;
};
GI_CHECK_SIZE(VoxelGridPush, 48);

// voxelize.comp: one dispatch per draw. info.x = 0: one invocation per triangle; info.x = 1:
// one work group per triangle (and row slice), its invocations sharing the triangle's columns.
// info.y = 1: positions in world voxels (world position / voxel edge + 1/2, no origin subtracted:
// world voxel k is centred on k times the edge, worldVoxelCorner in voxel_grid.hpp), the
// grid's min corner at world voxel `cell`: a clipmap level then makes the same float decisions
// for a voxel whatever its corner, so content kept across a move equals a fresh voxelization.
// Only voxels in [boxLo, boxHi] (grid voxels, inclusive) receive contributions: the whole grid,
// or the slab a moved level newly covers.
GI_GPU_STRUCT(VoxelizePush) {
    VoxelGridParams grid;
    uvec4 draw;  // x instance index, y first index, z triangle count, w vertex offset
    uvec4 info;  // x 1 = a work group per triangle, y 1 = world-voxel positions, z, w 0
    ivec4 cell;  // xyz: the grid's min corner in world voxels (info.y = 1; else 0), w 0
    ivec4 boxLo; // xyz: first grid voxel voxelized, w 0
    ivec4 boxHi; // xyz: last grid voxel voxelized, w 0
};
GI_CHECK_SIZE(VoxelizePush, 128);

// voxel_mark.comp (a moved clipmap level): sets the touched bit of every voxel of the last
// voxelization's touched list (indirect over it) at its place after the move, when the level
// still covers it, so the new touched list covers the kept voxels as well as the slabs' new ones.
GI_GPU_STRUCT(VoxelMarkPush) {
    VoxelGridParams grid;
    ivec4 move; // xyz: the corner's move in voxels (a kept voxel's index decreases by it), w 0
};
GI_CHECK_SIZE(VoxelMarkPush, 64);
#define VOXEL_MARK_BINDING_PREVIOUS 0 // touched list of the last voxelization (holds every nonzero voxel)
#define VOXEL_MARK_BINDING_BITS 1     // touched bits, bit x + N (y + N z)

// Touched-voxel lists of the grid (VoxelGrid; a pair used in turn for the static or whole-scene
// voxelization, one for the dynamic draws): voxelize.comp sets a voxel's touched bit when it
// makes the voxel's first contribution of a voxelization (its count atomic returned 0), and
// voxel_touched_list.comp lists the set bits, so every occupied voxel is listed once, in grid
// order within runs of 256 voxels along x. The resolve passes and the VCT list run over them
// instead of over N^3. A storage buffer of GI_VOXEL_TOUCHED_HEADER uints, the VkDispatchIndirectCommand
// (x = ceil(count / GI_VOXEL_LIST_GROUP), y = z = 1; the clear before a voxelization writes
// (0, 1, 1, 0)) then the count, followed by N^3 voxelListPack slots.
#define GI_VOXEL_TOUCHED_HEADER 4u
// Work-group size of the passes that run over a voxel list (one invocation per listed voxel).
#define GI_VOXEL_LIST_GROUP 64u
GI_INLINE uint voxelListPack(uvec3 c) { return c.x | (c.y << 10u) | (c.z << 20u); }
GI_INLINE uvec3 voxelListUnpack(uint v) { return uvec3(v & 1023u, (v >> 10u) & 1023u, v >> 20u); }

// Bindings (set 1).
#define VOXELIZE_BINDING_VERTICES 0     // GPU scene vertices (engine/scene_types.h)
#define VOXELIZE_BINDING_INDICES 1      // GPU scene indices
#define VOXELIZE_BINDING_INSTANCES 2    // GPU scene instances
#define VOXELIZE_BINDING_MATERIALS 3    // GPU scene materials
#define VOXELIZE_BINDING_TOUCHED_BITS 5 // touched bits, bit x + N (y + N z)
// The accumulation records (gi/voxel_grid.h): GI_VOXEL_ACC_SLABS ranges of whole z-layers at
// consecutive bindings from this one (voxel_acc.glsl; voxelize, resolve and merge).
#define VOXEL_ACC_BINDING_RECORDS 10
#define VOXEL_RESOLVE_BINDING_ALBEDO 1        // resolve, merge: albedo volume written
#define VOXEL_RESOLVE_BINDING_NORMAL 2        // normal volume written
#define VOXEL_RESOLVE_BINDING_EMISSION 3      // emission volume written
#define VOXEL_RESOLVE_BINDING_FACES 4         // faces volume written
#define VOXEL_RESOLVE_BINDING_STATIC_ALBEDO 5 // merge only: the static volumes' albedo (occupancy)
#define VOXEL_RESOLVE_BINDING_TOUCHED 9       // touched list the indirect dispatch runs over
#define VOXEL_STALE_BINDING_TOUCHED_BITS 0    // voxel_resolve_stale.comp: this voxelization's touched bits
#define VOXEL_STALE_BINDING_ALBEDO 1          // albedo volume (stale voxels zeroed)
#define VOXEL_STALE_BINDING_NORMAL 2          // normal volume
#define VOXEL_STALE_BINDING_EMISSION 3        // emission volume
#define VOXEL_STALE_BINDING_FACES 4           // faces volume
#define VOXEL_STALE_BINDING_PREVIOUS 9        // touched list of the last voxelization into the volumes
#define VOXEL_TOUCHED_BINDING_BITS 0          // voxel_touched_list.comp: touched bits (listed, then zeroed)
#define VOXEL_TOUCHED_BINDING_LIST 1          // the touched list it appends to

GI_NAMESPACE_END
#endif
