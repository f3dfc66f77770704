#version 460
#extension GL_GOOGLE_include_directive : require
// A large sun window's candidate VPLs weighted by their light on the frame's visible points,
// each term stopped by the voxel grid's occupancy as in the gather (gi/vpl_importance_pass.h,
// gi/vpl_visibility.h).
#define VPL_VISIBILITY_MARCH
#include "gi/vpl_importance_pass.h"
