// Emissive surfels (C++ and GLSL): emitting triangles sampled into an image set in the reflective
// shadow map's formats (gi/src/emissive/emissive_surfels.hpp), so that what injects or samples
// RSM texels takes light from emissive surfaces the same way. Texel k = (k mod R, k / R) of
// layer 0 is surfel k:
//   position RGBA32F  xyz world position on the triangle, w = 1 (0: no surfel)
//   normal   RGBA16F  xyz unit normal of the side that emits
//   flux     RGBA32F  rgb emitted flux (pi * Le * the triangle's area * weight, cd*sr like an RSM
//                     texel's), w = the surfel's area (the triangle's area * weight, m^2): the
//                     footprint of a VPL placed on it (docs/vpl.md, "Emitter VPLs")
// A Lambertian emitter of radiance Le sends pi Le per unit area, the radiant intensity of a
// surfel is then flux / pi * cos, as for an RSM texel's reflected flux.
#ifndef VKGI_GI_EMISSIVE_H
#define VKGI_GI_EMISSIVE_H
#include "../shared/bridge.h"

GI_NAMESPACE_BEGIN

// One surfel: which triangle and side, where on it, and its share of the triangle's flux.
GI_GPU_STRUCT(GpuEmissiveSurfel) {
    uvec4 triangle; // x instance, y triangle index within the instance's draw, z side (0 front, 1 back), w 0
    vec4 point;     // xy: point in the unit square (mapped uniformly onto the triangle), z weight, w 0
};
GI_CHECK_SIZE(GpuEmissiveSurfel, 32);

GI_GPU_STRUCT(EmissiveSurfelPush) {
    uvec4 info; // x surfel count, y image side R, z, w 0
};
GI_CHECK_SIZE(EmissiveSurfelPush, 16);

// Bindings (set 1) of surfels.comp.
#define EMISSIVE_BINDING_VERTICES 0  // GPU scene vertices (engine/scene_types.h)
#define EMISSIVE_BINDING_INDICES 1   // GPU scene indices
#define EMISSIVE_BINDING_INSTANCES 2 // GPU scene instances
#define EMISSIVE_BINDING_MATERIALS 3 // GPU scene materials
#define EMISSIVE_BINDING_SURFELS 4   // GpuEmissiveSurfel[count]
#define EMISSIVE_BINDING_POSITION 5  // output images (2D arrays, layer 0)
#define EMISSIVE_BINDING_NORMAL 6
#define EMISSIVE_BINDING_FLUX 7

GI_NAMESPACE_END
#endif
