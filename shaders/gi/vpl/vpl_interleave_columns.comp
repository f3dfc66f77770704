#version 460
#extension GL_GOOGLE_include_directive : require
// Interleaved gather, reconstruction along columns of the row pass's result
// (gi/vpl_interleave_filter.h), then the indirect radiance albedo/pi * E at each pixel.
#include "gi/vpl.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_2D, local_size_y = GI_VPL_LOCAL_SIZE_2D) in;
layout(push_constant) uniform PushBlock { VplPixelPush pc; };

layout(set = 1, binding = VPL_INTERLEAVE_COLUMNS_BINDING_POSITION) uniform sampler2D gPosition;
layout(set = 1, binding = VPL_INTERLEAVE_COLUMNS_BINDING_NORMAL) uniform sampler2D gNormal;
layout(set = 1, binding = VPL_INTERLEAVE_COLUMNS_BINDING_ALBEDO) uniform sampler2D gAlbedo;
layout(set = 1, binding = VPL_INTERLEAVE_COLUMNS_BINDING_ROWS_INCIDENT) uniform sampler2D filterIncident;
layout(set = 1, binding = VPL_INTERLEAVE_COLUMNS_BINDING_ROWS_TRAVEL) uniform sampler2D filterTravel;
layout(set = 1, binding = VPL_INTERLEAVE_COLUMNS_BINDING_INDIRECT, rgba32f) uniform writeonly image2D outIndirect;
layout(set = 1, binding = VPL_INTERLEAVE_COLUMNS_BINDING_INCIDENT, rgba32f) uniform writeonly image2D outIncident;
layout(set = 1, binding = VPL_INTERLEAVE_COLUMNS_BINDING_TRAVEL, rgba32f) uniform writeonly image2D outTravel;

#include "gi/vpl_interleave_filter.h"

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(px), pc.size.xy)))
        return;
    bool withTravel = pc.params.w > 0.0;
    vec3 e, travel;
    vplInterleaveFilter(px, ivec2(0, 1), withTravel, e, travel);
    vec3 radiance = texelFetch(gAlbedo, vplGbufferSample(px), 0).rgb * e * (1.0 / GI_VPL_PI);
    imageStore(outIndirect, px, vec4(radiance, 1.0));
    imageStore(outIncident, px, vec4(e, 0.0));
    if (withTravel)
        imageStore(outTravel, px, vec4(travel, 0.0));
}
