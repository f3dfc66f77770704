// Push-constant blocks of the voxel passes (C++ and GLSL). Each stays within lavapipe's
// 128-byte push-constant limit; sizes are pinned on both sides.
#ifndef VKGI_GI_VOXEL_PASSES_H
#define VKGI_GI_VOXEL_PASSES_H
#include "voxel_grid.h"

GI_NAMESPACE_BEGIN

// voxel_clear.comp, voxel_resolve*.comp: the grid only.
GI_GPU_STRUCT(VoxelGridPush) {
    VoxelGridParams grid;
};
GI_CHECK_SIZE(VoxelGridPush, 48);

// voxelize.comp: one dispatch per draw, one invocation per triangle of the draw.
GI_GPU_STRUCT(VoxelizePush) {
    VoxelGridParams grid;
    uvec4 draw; // x instance index, y first index, z triangle count, w vertex offset
};
GI_CHECK_SIZE(VoxelizePush, 64);

GI_NAMESPACE_END
#endif
