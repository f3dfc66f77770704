#version 460
#extension GL_GOOGLE_include_directive : require
// One axis of the filter of VCT's incoming diffuse light (a = AO): the geometry-aware separable
// tent the VPL reconstruction uses (gi/surface_filter.h), run along rows, then along columns.
// VCT runs it at full resolution after the upsample and refine (size.z = f = 1); for f > 1 a
// pixel of a 1/f image stands for the G-buffer pixel lowResSource gives. The light is filtered
// before any albedo is applied: with info.y the column pass applies each pixel's albedo and
// metallic, with the glossy light unfiltered. Pixels without geometry keep their value.
#include "gi/vct_passes.h"
#define GI_LOWRES_SOURCE_ONLY
#include "gi/lowres_upsample.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push { VctFilterPush pc; };
// Point reads only: storage images (lavapipe loads their texels faster than it fetches them
// through a sampler).
layout(set = 1, binding = VCT_FILTER_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(set = 1, binding = VCT_FILTER_BINDING_NORMAL, rgba16f) uniform readonly image2D gNormal;
layout(set = 1, binding = VCT_FILTER_BINDING_ALBEDO, rgba16f) uniform readonly image2D gAlbedo; // w = metallic
layout(set = 1, binding = VCT_FILTER_BINDING_INPUT, rgba32f) uniform readonly image2D inLight;
layout(set = 1, binding = VCT_FILTER_BINDING_GLOSSY, rgba32f) uniform readonly image2D inGlossy;
layout(set = 1, binding = VCT_FILTER_BINDING_OUTPUT, rgba32f) uniform writeonly image2D outLight;

#include "gi/surface_filter.h"

ivec2 sourcePixel(ivec2 q) { return lowResSource(q, int(pc.size.z), ivec2(pc.info.zw)); }

bool surfaceFilterNeighbour(ivec2 q, vec3 p, vec3 n, float invTolerance) {
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(pc.size.xy))))
        return false;
    ivec2 src = sourcePixel(q);
    vec4 position = imageLoad(gPosition, src);
    return position.w != 0.0 &&
           surfaceFilterSameSurface(p, n, position.xyz, normalize(imageLoad(gNormal, src).xyz), invTolerance);
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(px), pc.size.xy)))
        return;
    ivec2 src = sourcePixel(px);
    vec4 position = imageLoad(gPosition, src);
    vec4 light = imageLoad(inLight, px);
    if (position.w != 0.0) {
        vec3 n = normalize(imageLoad(gNormal, src).xyz);
        float invTolerance = 1.0 / max(pc.eye.w * distance(position.xyz, pc.eye.xyz), 1e-30);
        ivec2 axis = pc.info.x == 0u ? ivec2(1, 0) : ivec2(0, 1);
        int side = int(pc.size.w);
        int h = surfaceFilterHalfWidth(px, axis, side, position.xyz, n, invTolerance);
        vec4 sum = vec4(0.0);
        for (int d = -h; d <= h; ++d)
            sum += surfaceFilterWeight(d, h, side) * imageLoad(inLight, px + d * axis);
        light = sum / surfaceFilterClasses(h, side);
    }
    if (pc.info.y != 0u && position.w != 0.0) {
        vec4 albedo = imageLoad(gAlbedo, src);
        light.rgb = albedo.rgb * mix(light.rgb, imageLoad(inGlossy, px).rgb, clamp(albedo.w, 0.0, 1.0));
    }
    imageStore(outLight, px, light);
}
