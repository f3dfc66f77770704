#version 460
#extension GL_GOOGLE_include_directive : require
// Interleaved gather, reconstruction along columns of the row pass's result
// (gi/vpl_interleave_filter.h), then the indirect radiance albedo/pi * E at each pixel; pixels
// the filter could not give every subset go to the refine list.
#include "gi/vpl.h"
#include "gi/vpl_refine_list.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_2D, local_size_y = GI_VPL_LOCAL_SIZE_2D) in;
layout(push_constant) uniform PushBlock { VplPixelPush pc; };

layout(set = 1, binding = VPL_INTERLEAVE_COLUMNS_BINDING_SURFACE) uniform usampler2D filterSurface;
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
    // A pixel whose windows leave it at most 3 of the n^2 subsets (a window that could not leave
    // the pixel on one axis and at most 3 classes on the other: a corner, a one-pixel sliver) is
    // gathered again with every VPL at full resolution; at low resolution the upsample's own
    // discontinuity test refines the full-resolution pixels around it. Pixels left with 4 or
    // more subsets are kept: refining them too (at n = 4, every pixel next to an edge) cost more
    // than the rest of the gather for a small gain on the built-in scenes (docs/vpl.md).
    float rowClasses = texelFetch(filterIncident, px, 0).w;
    if (position.w > 0.0 && pc.size.z == 1u && rowClasses * classes < 3.5) {
        VPL_REFINE_LIST_APPEND(px, pc.size.w)
    }
    vec3 radiance = texelFetch(gAlbedo, vplGbufferSample(px), 0).rgb * e * (1.0 / GI_VPL_PI);
    imageStore(outIndirect, px, vec4(radiance, 1.0));
    if (withTravel) { // the negative VPLs read both
        imageStore(outIncident, px, vec4(e, 0.0));
        imageStore(outTravel, px, vec4(travel, 0.0));
    }
}
