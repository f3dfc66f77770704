#version 460
#extension GL_GOOGLE_include_directive : require
// The VPL gather with each VPL's light stopped where its visibility map says
// (gi/vpl_visibility.h, gi/vpl_gather_pass.h).
#define VPL_VISIBILITY
#define VPL_VISIBILITY_MAPS
#include "gi/vpl_gather_pass.h"
