#version 460
#extension GL_GOOGLE_include_directive : require
// Interleaved gather, reconstruction along rows (gi/vpl_interleave_filter.h); the column pass
// completes it. Writes the irradiance with the number of subset classes it covers in w.
#include "gi/vpl.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_2D, local_size_y = GI_VPL_LOCAL_SIZE_2D) in;
layout(push_constant) uniform PushBlock { VplPixelPush pc; };

layout(set = 1, binding = VPL_INTERLEAVE_ROWS_BINDING_SURFACE) uniform usampler2D filterSurface;
layout(set = 1, binding = VPL_INTERLEAVE_ROWS_BINDING_GATHER_INCIDENT) uniform sampler2D filterIncident;
layout(set = 1, binding = VPL_INTERLEAVE_ROWS_BINDING_GATHER_TRAVEL) uniform sampler2D filterTravel;
layout(set = 1, binding = VPL_INTERLEAVE_ROWS_BINDING_INCIDENT, rgba32f) uniform writeonly image2D outIncident;
layout(set = 1, binding = VPL_INTERLEAVE_ROWS_BINDING_TRAVEL, rgba32f) uniform writeonly image2D outTravel;

#include "gi/vpl_interleave_filter.h"

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(px), pc.size.xy)))
        return;
    bool withTravel = pc.params.w > 0.0;
    vec3 e, travel;
    float classes;
    vplInterleaveFilter(px, ivec2(1, 0), withTravel, e, travel, classes);
    imageStore(outIncident, px, vec4(e, classes));
    if (withTravel)
        imageStore(outTravel, px, vec4(travel, 0.0));
}
