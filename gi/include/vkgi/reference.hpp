#pragma once
// The ground truth: a CPU path tracer (Embree 3 + TBB) in the same units and camera
// conventions as the rasteriser, against which every GI technique's error is measured.
//
// Model (what "correct" means for the comparisons):
// - Lambertian everywhere: albedo = baseColor factor x baseColorTexture (bilinear, repeat,
//   sRGB-decoded when the texture is sRGB), clamped to [0,1]; metallic/roughness are ignored
//   (metals are treated as Lambertian for now). Alpha is ignored (everything is opaque).
// - Reflection is two-sided: a ray reaching the back of a single-sided surface is reflected
//   as from the front (the shading frame is flipped to the ray's side). Emission is
//   one-sided: a surface emits from its front face only (counter-clockwise winding, as glTF
//   defines it, corrected for mirroring transforms) unless its material is doubleSided.
// - Emission in nits, punctual lights in KHR_lights_punctual units through the shared
//   falloff in shaders/include/engine/lights.h (inverse square, range window, spot cone).
//   No environment: rays that leave the scene return zero.
// - Pixel centres only, exactly Camera::pixelRayDirection (no jitter, so no anti-aliasing):
//   the rasteriser samples pixel centres too, so edges line up between the two.
// - Estimator: next-event estimation for punctual lights (shadow rays) and for emissive
//   triangles (chosen by power = area x emission luminance, uniform by area within the
//   triangle), combined with cosine-weighted hemisphere sampling by MIS (power heuristic).
//   Shading normals from the mesh where present; the geometric normal decides which
//   directions leave the surface (a sampled direction below it ends the path, no leaks).
//   Rays leave a surface from the hit point moved off it along the geometric normal by a bound
//   on the float error of that point (its coordinates along the normal and the triangle's
//   size, rounded away from the surface), so at concave edges, acute ones and far from the
//   origin included, no ray starts behind the adjacent face; MIS weights measure distances
//   between the exact points, not from the moved origin.
//   Russian roulette after 3 reflections with continuation probability min(1, max(beta) / 0.1)
//   and beta divided by it (unbiased; beta = path throughput). Paths also stop after kMaxReflections reflections, a bias below
//   albedo^kMaxReflections (4e-5 relative at albedo 0.99) that only matters as albedo -> 1.
// - Deterministic: every (pixel, sample) has its own hash-seeded random stream, so the
//   output is bit-identical across runs and independent of the number of threads.
#include <cstdint>
#include <filesystem>

#include "vkgi/camera.hpp"
#include "vkgi/hdr_image.hpp"
#include "vkgi/result.hpp"
#include "vkgi/scene.hpp"

namespace vkgi::gi {

// Path length cap (see above): long enough that the furnace at albedo 0.99 is off by < 1e-4.
inline constexpr int kMaxReflections = 1024;

struct ReferenceSettings {
    uint32_t spp = 64;    // paths per pixel, all through the pixel centre
    int maxBounces = -1;  // -1 = unbounded; k = reflections between emitter and eye (0 = emitters only)
    uint64_t seed = 1;    // changes every random stream; same seed = same image
    bool progress = true; // progress bar with ETA on stderr, only when stderr is a terminal
};

struct ReferenceImages {
    HdrImage full;     // all paths (within maxBounces)
    HdrImage direct;   // emission seen directly + light after exactly one reflection
    HdrImage indirect; // paths with >= 2 reflections; full = direct + indirect up to rounding
    double seconds = 0.0; // wall time of the render (of the original render when loaded from cache)
    uint64_t rays = 0;    // camera + continuation + shadow rays traced
};

// Renders full/direct/indirect in one pass (contributions are binned by path length).
// Errors (one line) for: no geometry, width/height 0 or > 16384, spp 0, maxBounces < -1,
// non-finite or negative light/material values, non-finite vertices/transforms, bad indices.
Result<ReferenceImages> renderReference(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                                        const ReferenceSettings& settings);

// FNV-1a 64 hash of everything that changes the rendered image: geometry, materials,
// textures, instances, lights, camera pose and fov, resolution, spp, maxBounces, seed and
// the tracer's version (not names, not `progress`, not znear/zfar, not `dynamic` flags).
uint64_t referenceHash(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                       const ReferenceSettings& settings);

// The cache folder: $VKGI_CACHE_DIR if set and non-empty, else $HOME/.cache/vkgi
// (else the system temp folder /vkgi-cache when HOME is unset).
std::filesystem::path referenceCacheDir();

// The cache entry's full-image EXR: <dir>/ref-<16 hex digits>.full.exr. Its siblings
// .direct.exr, .indirect.exr and .json (seconds, rays; written last, marks the entry complete).
std::filesystem::path referenceCacheFile(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                                         const ReferenceSettings& settings);

// renderReference through the cache: loads a complete entry when present, else renders and
// stores it (creating the folder). A failure to store does not lose the render: the images
// are returned and a one-line warning goes to stderr. `fromCache` tells which happened.
Result<ReferenceImages> renderReferenceCached(const Scene& scene, const Camera& camera, uint32_t width,
                                              uint32_t height, const ReferenceSettings& settings,
                                              bool* fromCache = nullptr);

} // namespace vkgi::gi
