#pragma once
// Image-space instant radiosity after Cochran & Steele, "Second-Order Illumination in
// Real-Time": VPLs placed by Halton points inside each spot cone and projected into the
// shared RSM, deferred VPL shading over the G-buffer (interleaved: each pixel of a tile gathers a
// subset, filtered back), without visibility as in the paper or marched through a voxel grid,
// negative VPLs for the missing occlusion, and a low-resolution gather refined at
// discontinuities. See docs/vpl.md.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "vkgi/camera.hpp"
#include "vkgi/result.hpp"
#include "vkgi/rg/render_graph.hpp"

namespace vkgi {
class Context;
}

namespace vkgi::gi {

// Most VPLs per light, negative VPLs and lights (mirror GI_VPL_MAX_* in gi/vpl.h).
constexpr uint32_t kMaxVplsPerLight = 4096;
constexpr uint32_t kMaxNegativeVpls = 4096;
constexpr uint32_t kMaxVplLights = 8;
// Largest interleave tile side: the filter reads (2n - 1)^2 neighbours (mirrors GI_VPL_MAX_INTERLEAVE).
constexpr uint32_t kMaxVplInterleave = 4;
// Most VPL generations (VplSettings::bounces): each costs one more gather of N VPLs per light,
// and the fourth bounce already carries rho^3 of the first's light.
constexpr uint32_t kMaxVplBounces = 4;
// Most candidates per VPL of a large sun window (VplSettings::candidates): the importance pass
// costs candidates x sampled pixels visibility marches.
constexpr uint32_t kMaxVplCandidates = 16;
// Halton indices searched for the points of one cone before giving up: 2^22 bounds the CPU
// search and still serves 4096 VPLs in a cone of half-angle >= ~3.6 degrees.
constexpr uint32_t kMaxHaltonSearch = 1u << 22;

// Visibility between VPLs and receivers (VplSettings::visibility).
enum class VplVisibilityMode : uint32_t {
    Off,  // none, as in the paper
    On,   // each VPL's light marched through the voxel grid's occupancy, per receiver
    Auto, // On with a directional light or emission, else Maps with a point light, else Off (resolveVplSettings)
    Maps, // each VPL's light stopped where its visibility map (rays walked once per VPL) says
};

// Where the visibility (and bounce) grid goes (VplSettings::visibilityPlacement).
enum class VplGridPlacement : uint32_t {
    Auto,   // fitted, or centred on the camera in a large world (the rule in docs/vpl.md, "Visibility")
    Fitted, // fitted to the scene's bounds, whatever their size
    Camera, // centred on the camera, its voxels set in metres
};

// The knobs of the VPL technique (what vkgi-bench sweeps).
struct VplSettings {
    // Positive VPLs per light, 1..kMaxVplsPerLight. 256 = 16 per subset of the default 4 x 4
    // interleave tile, so all subsets are equal (the choice and its measurement: docs/vpl.md).
    uint32_t vplCount = 256;
    uint32_t negativeVplCount = 0;   // negative VPLs (0 = off), 0..kMaxNegativeVpls
    uint32_t lowResFactor = 1;       // indirect light at 1/factor resolution per axis: 1 (off), 2 or 4
    float refineThreshold = 0.1f;    // discontinuity test: 1 - dot(normals) or |dp| / depth above it refines
    // Clamp of the 1/d^2 term near a VPL, in units of the VPL's footprint radius r (the radius of
    // the disc of surface one VPL stands for: its share of what the RSM saw): d^2 is replaced by
    // max(d^2, (clampDistance * r)^2). It removes the bright splotches next to VPLs at the cost
    // of darkening contact regions, and follows the VPLs' spacing, so it means the same in a
    // box and in a city. The default is the bench's choice (docs/vpl.md).
    float clampDistance = 1.0f;
    // Directional lights: where the light's window is more than twice this radius (metres,
    // 0.01..1e5) from its centre to a corner, as in a level much larger than the view, its VPLs
    // concentrate around the camera with the density of a 2D Student-t of this radius (pdf of r
    // proportional to 1 / (1 + r^2 / R^2)^2, positive everywhere, so nothing lit is left out),
    // on lattices fixed to the world, each point standing for its lattice cell: unbiased over
    // the lattices' offsets (focusedWindowPoints). Smaller windows keep the uniform Halton
    // points of the paper.
    float focusRadius = 16.0f;
    // Such a focused window's VPLs drawn from world-fixed candidates, this many per VPL on the
    // same lattices made denser, by their estimated contribution to the frame (the light each
    // brings to a sparse set of visible points, through the visibility grid), with priority
    // sampling so that the estimate stays unbiased and a moving camera changes few of them
    // (docs/vpl.md, "Candidates weighted by the image"). 0 = the lattice points themselves,
    // 1..16.
    uint32_t candidates = 8;
    // Interleaved sampling: each pixel of an n x n tile gathers 1/n^2 of the VPLs and a
    // geometry-aware tent filter over the tile sums the subsets back (docs/vpl.md). 1 = off
    // (every pixel gathers every VPL); 2, 3 or 4. 4 by default: the bench's choice for the
    // frame's cost at the full gather's error (docs/vpl.md, "Defaults").
    uint32_t interleave = 4;
    // The interleave filter's plane test: a neighbour further than this fraction of the
    // pixel's distance to the camera off the pixel's tangent plane is another surface.
    float interleaveTolerance = 0.02f;
    // Visibility between VPLs and receivers: each VPL's light is marched through the occupancy
    // of a voxel grid of visibilityGrid^3 around the scene or the camera (the grid LPV shares,
    // built only when this or bounces need it), so light does not pass through walls
    // (docs/vpl.md), or looked up in per-VPL visibility maps (Maps: rays walked once per VPL).
    // Auto by default: on where a directional light shines in, whose light reaches interiors
    // through openings and whose VPLs otherwise light them through the walls, and where emissive
    // surfaces shine, whose emitter VPLs carry their direct light, which needs its shadows; maps
    // where a point light shines, which also lights the surface it hangs from, so that VPLs in a
    // small patch there carry much of its reflected light through every occluder; off with
    // spotlights only, the paper's setting (resolveVplSettings; the measurements behind it in
    // docs/vpl.md, "Defaults", "Emitter VPLs" and "Visibility maps").
    VplVisibilityMode visibility = VplVisibilityMode::Auto;
    uint32_t visibilityGrid = 64; // voxels per axis, a power of two 16..256 (also the bounces' grid)
    // Where that grid goes. Auto: fitted to the scene, except where the camera is inside the
    // scene's bounds and a fitted voxel would be much coarser than a metre-scale one (a level
    // hundreds of metres wide, whose fitted voxels close every doorway): then a box of 64 m per
    // axis centred on the camera, moved in quarter-grid steps (docs/vpl.md, "Visibility").
    VplGridPlacement visibilityPlacement = VplGridPlacement::Auto;
    // Indirect bounces the VPLs model, 1..kMaxVplBounces (instant radiosity, Keller 1997): 1 is
    // the paper's one bounce; each further one traces one ray per VPL of the last generation,
    // cosine-distributed about its normal, through the voxel grid's occupancy to the first
    // occupied voxel, where a VPL of the next generation sits with the parent's flux times the
    // albedo there (docs/vpl.md, "Multi-bounce VPLs"). The grid is the visibility one
    // (visibilityGrid), built when either needs it. 0 = automatic: 2 where visibility is on
    // (the grid exists anyway and the bounced light then no longer leaks), else 1
    // (resolveVplSettings).
    uint32_t bounces = 0;

    bool operator==(const VplSettings&) const = default;
};

// Checks every knob; the error names the knob, its value and the allowed range.
Result<void> validateVplSettings(const VplSettings& settings);

// The kinds of light the automatic VPL settings depend on (resolveVplSettings).
enum class VplLighting : uint32_t {
    Spots,         // spotlights only, or no light
    PointLights,   // a point light, and no directional light or emission
    SunOrEmission, // a directional light or emissive surfaces
};

// The automatic settings made explicit for a scene's lighting: visibility Auto becomes On (the
// march per receiver) with a sun or emission, Maps with a point light, Off with spotlights
// only; bounces 0 becomes 2 when visibility is then on, else 1. Explicit values are kept.
VplSettings resolveVplSettings(const VplSettings& settings, VplLighting lighting);

// The `count` first Halton points (bases 2 and 3, index 1, 2, ...) on the unit sphere whose
// angle to +Z is within the cone of cosine `cosOuter`, in order: exactly the paper's
// placement, in the light's local frame. Deterministic; a cone too narrow to find `count`
// points within kMaxHaltonSearch indices is an error.
Result<std::vector<glm::vec3>> spotSampleDirections(uint32_t count, float cosOuter);

// Orthonormal right-handed frame (columns x, y, z) whose z is the unit spot `direction`: the
// smallest rotation taking -Y to `direction`, applied to the frame (X, +Z, -Y). It turns
// smoothly with the light everywhere except at direction = +Y (a spot pointing straight up),
// where the twist about the axis is undefined and jumps.
glm::mat3 spotFrame(const glm::vec3& direction);

// Solid angle of a cone of half-angle acos(cosOuter): 2 pi (1 - cosOuter).
inline float coneSolidAngle(float cosOuter) { return 6.28318530718f * (1.0f - cosOuter); }

// One light that owns RSM layers: a spotlight (the paper's case), a point light (a spot whose
// cone is the whole sphere, cosOuter = -1, on its six cube layers) or a directional light
// (`directional`: one orthographic layer; position, direction and cosOuter are unused, the VPLs
// are Halton points of the layer's window, docs/vpl.md).
struct VplSpot {
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f}; // unit spot axis
    float cosOuter = 0.7071068f;            // cosine of the outer cone half-angle
    uint32_t firstLayer = 0;                // its layers in the RSM arrays and the shadow views table
    uint32_t layerCount = 1;                // 1 (perspective or orthographic layer) or 6 (cube)
    bool directional = false;
    glm::mat4 window{1.0f}; // directional: the RSM layer's orthographic view-projection
};

// The `count` first Halton points (bases 2 and 3, index 1, 2, ...) of the square [-1, 1]^2,
// as (x, y, 0): where a directional light's VPLs sample its orthographic RSM window.
std::vector<glm::vec3> windowSamplePoints(uint32_t count);

// Whether a directional light's window (its layer's orthographic view-projection) is large
// enough for focused points: its centre-to-corner distance exceeds twice `radius` (metres).
bool windowIsFocused(const glm::mat4& windowViewProj, float radius);

// A focused window's samples (docs/vpl.md, "A sun over a large world"): the points of lattices
// fixed to the world on the plane across the light, one lattice per ring around the camera's
// place (radii 0, R/2, R, 2R, 4R, ...; the place snaps to R/4), each ring's spacing giving it its
// share of the density p(r) = 1 / (pi R^2 (1 + r^2/R^2)^2) of `count` points, clipped to the
// window. `samples[k]` is (NDC x, NDC y, window area in m^2 the point stands for); empty slots
// lie beyond the window. A point's interleaved subset (of `subsets`, a square) is its lattice
// class, and `ids[k]` names it for the bounce rays of its children, so a point keeps both while
// the camera moves; a moved camera changes only the points that cross a ring.
struct FocusedWindowSamples {
    std::vector<glm::vec3> samples;
    std::vector<uint32_t> ids;
};
FocusedWindowSamples focusedWindowPoints(const glm::mat4& windowViewProj, const glm::vec3& camera, float radius,
                                         uint32_t count, uint32_t subsets);

// The `count` first Halton points (index 1, 2, ...) of generation `generation` >= 1's bounce
// bases (5, 7; then 11, 13; then 17, 19) mapped to the cosine-weighted hemisphere about +Z
// (pdf cos / pi): the local directions of one generation's bounce rays.
std::vector<glm::vec3> bounceSampleDirections(uint32_t count, uint32_t generation);

// The emitter source's table entries (docs/vpl.md, "Emitter VPLs"): sample k of `count` takes
// surfel `x` of as many emissive surfels (y = z = 0), the rank of k's radical inverse (base 2)
// among the count's, so that every contiguous run of samples (an interleaved subset's block)
// takes surfels spread over all emitters, as a Halton run spreads over a cone.
std::vector<glm::vec3> emitterSampleOrder(uint32_t count);

// What the VPL passes read. Image layouts as documented in vkgi/frame_data.hpp.
struct VplInputs {
    rg::ImageHandle gPosition; // RGBA32F world position, w = 1 where geometry was drawn
    rg::ImageHandle gNormal;   // unit normal
    rg::ImageHandle gAlbedo;   // Lambertian albedo
    uint32_t width = 0;        // G-buffer size
    uint32_t height = 0;
    Camera camera;
    rg::ImageHandle rsmPosition; // RSM 2D arrays (position, normal, flux per texel)
    rg::ImageHandle rsmNormal;
    rg::ImageHandle rsmFlux;
    rg::BufferHandle shadowViews; // GpuShadowView per layer (gi/direct_types.h)
    std::vector<VplSpot> spots;   // at most kMaxVplLights
    // With VplSettings::visibility: the voxel grid's albedo volume (RGBA8 3D, a = occupancy,
    // gi/voxel_grid.h), its min corner and voxel edge, and its voxels per axis.
    rg::ImageHandle occupancy;
    rg::ImageHandle faces; // with VplSettings::bounces > 1: the grid's faces volume (R32UI, voxelFacesPack)
    glm::vec4 occupancyOriginSize{0.0f};
    uint32_t occupancyResolution = 0;
    // Optional (a camera-centred grid): the grid's emission volume, whose alpha holds each voxel's
    // 2x2x2 half-voxel occupancy bits (gi/voxel_grid.h). When valid the visibility march and the
    // bounce rays test occupancy on half voxels (docs/vpl.md, "Visibility"); a bounce's hit still
    // reads `occupancy`'s albedo and `faces`.
    rg::ImageHandle occupancyHalves;
    // Emitter VPLs (docs/vpl.md, "Emitter VPLs"): emissive surfels in gi/emissive.h's layout (2D
    // arrays, layer 0), `emitterSurfels` of them on a side of `emitterResolution` texels; 0
    // surfels = the scene emits nothing. The emitters are one more source after the spots.
    rg::ImageHandle emitterPosition;
    rg::ImageHandle emitterNormal;
    rg::ImageHandle emitterFlux;
    uint32_t emitterSurfels = 0;
    uint32_t emitterResolution = 0;
};

struct VplOutputs {
    rg::ImageHandle indirect;     // RGBA32F indirect radiance (nits) at the G-buffer size
    rg::BufferHandle vpls;        // VplRecord per positive VPL, in the interleaved subset order
                                  // (gi/vpl.h; with bounces > 1 each light's generations are
                                  // sources of their own); spot after spot when interleave = 1
    rg::BufferHandle negativeVpls; // VplRecord per negative VPL (invalid when off)
    rg::BufferHandle refineList;  // gi/vpl_refine_list.h (invalid when lowResFactor = interleave = 1)
    uint32_t vplCount = 0;        // records in `vpls`
    // Large sun windows with VplSettings::candidates > 0: VplRecord per candidate (suns after
    // one another), from which vpl.select drew those suns' VPLs (invalid without such a sun).
    rg::BufferHandle candidates;
    uint32_t candidateCount = 0;
};

// The VPL technique: its pipelines and cached Halton directions; the passes are added per
// frame. GiSystem runs it as Technique::Vpl; tests and tools may drive it directly on their own
// G-buffer and RSM.
class VplTechnique {
public:
    static Result<std::unique_ptr<VplTechnique>> create(Context& ctx);
    ~VplTechnique();
    VplTechnique(const VplTechnique&) = delete;
    VplTechnique& operator=(const VplTechnique&) = delete;

    // Adds the VPL passes (upload, generate, [emitter], [bounces], gather, [negative VPLs],
    // [upsample + refine]). Automatic settings are resolved here for `inputs.spots`
    // (resolveVplSettings). Without spots and emitter surfels it adds one pass that clears
    // `indirect` (GiSystem does not call it then: a scene with no light and no emission gets no
    // VPL pass at all). Errors: bad settings, too many spots, a cone
    // too narrow for the requested VPL count.
    Result<VplOutputs> addPasses(rg::RenderGraph& graph, const VplInputs& inputs, const VplSettings& settings);

private:
    struct Impl;
    explicit VplTechnique(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m;
};

} // namespace vkgi::gi
