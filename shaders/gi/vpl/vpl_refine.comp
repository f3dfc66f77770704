#version 460
#extension GL_GOOGLE_include_directive : require
// The refine pass without visibility, as in the paper (gi/vpl_refine_pass.h).
#include "gi/vpl_refine_pass.h"
