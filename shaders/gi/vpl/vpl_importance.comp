#version 460
#extension GL_GOOGLE_include_directive : require
// A large sun window's candidate VPLs weighted by their light on the frame's visible points,
// without visibility (gi/vpl_importance_pass.h).
#include "gi/vpl_importance_pass.h"
