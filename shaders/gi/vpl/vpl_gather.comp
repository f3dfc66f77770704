#version 460
#extension GL_GOOGLE_include_directive : require
// The VPL gather without visibility, as in the paper (gi/vpl_gather_pass.h).
#include "gi/vpl_gather_pass.h"
