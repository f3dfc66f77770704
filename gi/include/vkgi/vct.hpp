#pragma once
// Voxel cone tracing (Crassin et al. 2011, with the deferred voxel shading of Villegas &
// Ramirez): the knobs a caller or vkgi-bench may turn, and their validation.
#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

#include "vkgi/camera.hpp"
#include "vkgi/result.hpp"
#include "vkgi/scene.hpp"

namespace vkgi::gi {

// How voxel direct lighting decides whether a light reaches a voxel.
enum class VctOcclusion : uint32_t {
    RayMarchHard = 0, // one ray through the occupancy volume
    RayMarchSoft = 1, // a cone through the occupancy volume (penumbra from the aperture)
    ShadowMap = 2,    // the light's shadow map (from the shared shadow pass)
};

// Where a voxel's opacity is pre-filtered (docs/vct.md "Pre-filtered opacity"): the share of its
// cross-section its surfaces block, instead of the whole voxel its conservative voxelization
// touched.
enum class VctPrefilter : uint32_t {
    Clipmap = 0, // in the clipmap's levels (levels > 1), not in a fitted grid
    Off = 1,
    On = 2,
};

// Widest diffuse cone half-angle (radians). A sample at distance t along a cone whose direction
// makes cos = rise with the surface normal reads texels at most rise * t / 1.5 wide, or their
// filter would reach the surface the cone starts from (the level cap, docs/vct.md "Cones"). A
// cone of half-angle a is 2 t tan(a) wide there, so every half-angle from atan(1/3) = 0.3218
// (18.4 degrees) on reads the same texels: the cap sets the width, not the angle. 21/64 is just
// above atan(1/3) and exact in a float and in text (the knob prints and parses it).
inline constexpr float kVctMaxDiffuseAperture = 0.328125f;

struct VctSettings {
    // Voxels per axis, a power of two in [16, 256].
    uint32_t gridResolution = 64;
    // Grid box; empty = fitted to the scene bounds (cubic voxels, half a voxel of margin).
    std::optional<Aabb> gridBox;
    // Diffuse cones per pixel over the normal hemisphere (1..32) and their half-angle (radians,
    // at most kVctMaxDiffuseAperture; the level cap narrows cones off the normal further, to
    // atan(rise / 3)).
    uint32_t diffuseCones = 6;
    float diffuseAperture = kVctMaxDiffuseAperture;
    // Distance between cone samples in units of the current cone diameter (0 < f <= 4).
    float stepFactor = 1.0f;
    // Light bounces carried by the voxels: 1 = direct light only, 2 = plus a per-voxel gather,
    // 3 = plus a second gather over the two-bounce radiance (docs/vct.md "Bounces").
    uint32_t bounces = 2;
    // Per-pixel cones at 1/lowResFactor resolution per axis (1, 2 or 4), bilinearly upsampled;
    // pixels whose low-res neighbours lie across a discontinuity (background, normals or
    // tangent-plane distance beyond refineThreshold, as the VPL low-res gather) are traced at
    // full resolution. Default 4: at 128^2 and 256^2 the error against the path tracer is that of
    // 2 within 1% (docs/vct.md) for fewer traced pixels.
    uint32_t lowResFactor = 4;
    float refineThreshold = 0.1f;
    // Side n of the geometry-aware tent (the VPL reconstruction's, docs/vct.md "Filter") over the
    // full-resolution incoming diffuse light, before the albedo: offsets |d| < n pixels along rows
    // and columns, cut where the pixel's surface ends. 1 = off, at most kVctMaxFilter. Smooths
    // the blotches the coarse voxels leave on curved surfaces; the default is the bench's choice
    // (docs/vct.md).
    uint32_t filter = 5;
    bool glossy = true;          // glossy cone whose aperture follows the roughness
    bool ambientOcclusion = true;
    float aoDistance = 0.0f;     // Villegas' AO decay distance in metres; 0 = 1/8 of the grid
    bool softShadows = false;    // cone-traced shadows of punctual lights
    float shadowAperture = 0.05f; // half-angle of the shadow cone (radians)
    // The shadow map by default: it finds which of the light's rays reach each voxel's surface,
    // where the march stops at whole conservative voxels and narrows openings by a voxel
    // (docs/vct.md "Visibility"). Graphs without the direct-light passes fall back to the march.
    VctOcclusion occlusion = VctOcclusion::ShadowMap;
    // Clipmap levels (0..8). 1: one grid fitted to the scene bounds or gridBox. 2..8: camera-following
    // levels of gridResolution^3 voxels each, level l with voxels of `voxel` * 2^l metres, so what
    // the grid resolves does not depend on how far the scene extends (docs/vct.md "Clipmap").
    // Memory grows as levels * gridResolution^3, so a clipmap wants a smaller gridResolution than
    // the fitted grid (the memory of each choice: docs/vct.md "Clipmap").
    // 0 (default) = automatic, decided when a scene is set: kVctAutoLevels levels of
    // kVctAutoLevelResolution^3 when the scene's camera is inside its bounds and the fitted grid's
    // voxels would be coarser than the clipmap's coarsest level (a viewer inside a level much
    // larger than the view), else the fitted grid of gridResolution^3.
    uint32_t levels = 0;
    // Voxel edge of the finest clipmap level in metres (levels > 1); 0 = automatic: the finest
    // level spans kVctAutoFinestSpan metres.
    float voxel = 0.0f;
    // Pre-filtered voxel opacity: a voxel blocks the share of its cross-section that its
    // surfaces' area projects onto, not the whole voxel its conservative voxelization touched.
    // Clipmap levels only by default: it lowers the large worlds' error and their sensitivity to
    // where walls straddle voxels, but lets the room's sun through the edges of its windows
    // (docs/vct.md "Pre-filtered opacity").
    VctPrefilter prefilter = VctPrefilter::Clipmap;

    bool operator==(const VctSettings&) const = default;
};

// Span (metres) of the finest clipmap level when VctSettings::voxel is 0: a hall around the
// camera, 0.5 m voxels at 32^3 (levels of 16 to 128 m). Finer finest levels measured worse on
// both large worlds (docs/vct.md "Clipmap": 8 m gave hall_world 0.280, atrium_world 0.247
// indirect relMSE, 16 m 0.276 and 0.233, 4 m 0.339 on atrium_world).
inline constexpr float kVctAutoFinestSpan = 16.0f;
// Largest VctSettings::filter side: each pass reads 2n - 1 texels per pixel, and a tent 15
// pixels wide already spans several voxels at the bench's sizes.
inline constexpr uint32_t kVctMaxFilter = 8;
// Most clipmap levels (VctSettings::levels).
inline constexpr uint32_t kVctMaxLevels = 8;
// The clipmap the automatic setting (levels = 0) picks: the bench's choice (docs/vct.md).
inline constexpr uint32_t kVctAutoLevels = 4;
inline constexpr uint32_t kVctAutoLevelResolution = 32;

// What VctSettings::levels = 0 resolves to for `scene` seen from `camera`: `settings` with
// levels (and for a clipmap gridResolution) set; other values are returned unchanged.
VctSettings resolveVctLevels(const VctSettings& settings, const Aabb& bounds, const Camera& camera);

// Voxel edge (metres) of the finest clipmap level of `settings` (levels > 1).
float vctFinestVoxel(const VctSettings& settings);

// Readable error for settings the passes cannot run with (grid not a power of two, no cones,
// non-finite or out-of-range apertures and step factors).
Result<void> validateVctSettings(const VctSettings& settings);

} // namespace vkgi::gi
