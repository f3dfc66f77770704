// GLSL only: the refine list, the pixels gathered again with every VPL (vpl_refine.comp), shared
// by the passes that append to it (the upsample's discontinuities, the interleave filter's
// incomplete pixels) and the refine pass. Layout (VPL_REFINE_LIST_HEADER_BYTES of header):
// a uint count, then the refine pass's VkDispatchIndirectCommand (x: work groups of
// GI_VPL_LOCAL_SIZE_1D entries, counted up by the appenders; y = z = 1 from the clear), then one
// packed pixel x | y << 16 per entry.
#ifndef VKGI_GI_VPL_REFINE_LIST_H
#define VKGI_GI_VPL_REFINE_LIST_H
#include "vpl.h"

// Declares the list at `bindingIndex` of set 1; `access` is readonly for the refine pass.
#define VPL_REFINE_LIST_BUFFER(bindingIndex, access)                                                  \
    layout(set = 1, binding = bindingIndex, std430) access buffer RefineList {                       \
        uint refineCount;                                                                           \
        uint refineGroupsX;                                                                         \
        uint refineGroupsY;                                                                         \
        uint refineGroupsZ;                                                                         \
        uint refinePixels[];                                                                        \
    }

// Appends px when the list (of `capacity` entries) has room; the first entry of each group of
// GI_VPL_LOCAL_SIZE_1D adds one work group to the refine pass's dispatch.
#define VPL_REFINE_LIST_APPEND(px, capacity)                                                          \
    {                                                                                               \
        uint slot_ = atomicAdd(refineCount, 1u);                                                    \
        if (slot_ < (capacity)) {                                                                   \
            refinePixels[slot_] = uint((px).x) | (uint((px).y) << 16);                              \
            if (slot_ % GI_VPL_LOCAL_SIZE_1D == 0u)                                                 \
                atomicAdd(refineGroupsX, 1u);                                                       \
        }                                                                                           \
    }

#endif
