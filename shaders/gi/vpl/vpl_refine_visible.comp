#version 460
#extension GL_GOOGLE_include_directive : require
// The refine pass with each VPL's light stopped by the voxel grid's occupancy
// (gi/vpl_visibility.h, gi/vpl_refine_pass.h).
#define VPL_VISIBILITY
#define VPL_VISIBILITY_MARCH
#include "gi/vpl_refine_pass.h"
