#version 460
#extension GL_GOOGLE_include_directive : require
// Interleaved gather, reconstruction along columns of the row pass's result
// (gi/vpl_interleave_filter.h), then the indirect radiance albedo/pi * E at each pixel; pixels
// the filter could not give every subset go to the refine list.
#include "gi/vpl.h"
#include "gi/vpl_refine_list.h"

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
VPL_REFINE_LIST_BUFFER(VPL_INTERLEAVE_COLUMNS_BINDING_REFINE_LIST, );

#include "gi/vpl_interleave_filter.h"

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(px), pc.size.xy)))
        return;
    bool withTravel = pc.params.w > 0.0;
    vec3 e, travel;
    float classes;
    vec4 position = vplInterleaveFilter(px, ivec2(0, 1), withTravel, e, travel, classes);
    // A window that could not leave the pixel in x or in y (an edge on both sides, or a one-pixel
    // sliver) holds one subset class on that axis, 1/n of the VPLs at most: at full resolution
    // the pixel is gathered again with every VPL; at low resolution the upsample's own
    // discontinuity test refines the full-resolution pixels around it. Windows cut to 3 of 4
    // classes are kept: the refine would cost more than the error it removes.
    float rowClasses = texelFetch(filterIncident, px, 0).w;
    if (position.w > 0.0 && pc.size.z == 1u && min(rowClasses, classes) < 1.5) {
        VPL_REFINE_LIST_APPEND(px, pc.size.w)
    }
    vec3 radiance = texelFetch(gAlbedo, vplGbufferSample(px), 0).rgb * e * (1.0 / GI_VPL_PI);
    imageStore(outIndirect, px, vec4(radiance, 1.0));
    imageStore(outIncident, px, vec4(e, 0.0));
    if (withTravel)
        imageStore(outTravel, px, vec4(travel, 0.0));
}
