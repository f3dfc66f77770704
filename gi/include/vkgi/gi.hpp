#pragma once
// vkgi's public GI API. A GiSystem renders a scene with direct lighting (G-buffer, shadow maps,
// deferred shading) plus the indirect light of the selected technique: as a whole frame
// (renderFrame, or renderIndirect on the host's G-buffer: build graph, execute, submit, wait),
// recorded into the host's command buffer (record), or as passes added to the host's own render
// graph (addPasses). Every pass goes through vkgi::rg, so unrequested work is culled and every
// pass can be timed. Every call that can fail returns a Result, a failed Vulkan call included:
// those are neither thrown to the host nor fatal (docs/embedding.md, "Errors").
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "vkgi/camera.hpp"
#include "vkgi/context.hpp"
#include "vkgi/hdr_image.hpp"
#include "vkgi/result.hpp"
#include "vkgi/rg/blackboard.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/scene.hpp"
#include "vkgi/lpv.hpp"
#include "vkgi/vct.hpp"
#include "vkgi/vpl.hpp"

namespace vkgi::gi {

// The indirect-light technique. None = direct lighting (+ emission) only.
enum class Technique : uint32_t { None = 0, Lpv = 1, Vct = 2, Vpl = 3 };

// "none", ...; the names the CLI accepts.
const char* toString(Technique technique);
std::vector<std::string> techniqueNames();
struct GiSettings;
// Reflections between emitter and eye `settings.technique` models with these settings (none: 1 =
// direct light only; one indirect bounce: 2; vct.bounces = 2 and lpv.bounces add one): the
// path-tracer bounce count to compare against. Automatic knobs that depend on the scene
// (vpl.bounces 0) are resolved for `scene`, or as for a scene without a directional light. vpl
// in a scene lit only by emission: vpl.bounces (its emitter VPLs give the emitters' direct light,
// one reflection, which the raster direct image leaves out).
int modelledBounces(const GiSettings& settings, const Scene* scene = nullptr);
// Parses a name from techniqueNames(); the error lists the valid names.
Result<Technique> parseTechnique(std::string_view name);

// Largest GiSettings::shadowCascades: each cascade is an atlas layer re-rendered when the camera
// moves, and past 8 the log splits give the nearest slice less depth than znear on usual views.
constexpr uint32_t kMaxShadowCascades = 8;

struct GiSettings {
    Technique technique = Technique::None;
    // Texels per side of each shadow-map (and RSM) layer: 256 keeps a cube light's RSM (40 bytes
    // per texel over 6 layers) well inside the module's memory budget.
    uint32_t shadowMapSize = 256;
    // Atlas layers (a spot/directional light takes 1, a point light or wide spot 6); lights past
    // the limit are unshadowed. Cascades, then a technique's shadow windows (docs/direct.md
    // "Windows"), take what is left. The default bounds the atlas's memory at the default layer
    // size.
    uint32_t maxShadowLayers = 64;
    // Shadow cascades per directional light (0..8, 0 = off; docs/direct.md): shadow-only atlas
    // layers fitted to slices of the camera's view depth, which the deferred direct pass reads
    // instead of the light's whole-scene layer, so shadow texels do not grow with the scene.
    // They count against maxShadowLayers after every light's own layers, are re-rendered when the
    // camera moves by a texel or more. Only the cascades with finer texels than the whole-scene
    // layer are kept (the near ones where the camera sees most of the scene); receivers beyond
    // them use the whole-scene layer.
    uint32_t shadowCascades = 4;
    // PCF kernel (2r+1)^2 of bilinear compares; 1 = 3x3 softens the 1-texel stair steps.
    uint32_t pcfRadius = 1;
    // Shadow biases in shadow-texel world sizes at the receiver: a normal offset and a depth
    // bias below the receiver's tangent plane, which every PCF texel is compared against
    // (deferred.comp), so no slope-scaled term is needed.
    float shadowNormalOffset = 0.0f;
    float shadowConstantBias = 0.5f;
    // Render the reflective shadow map even when the technique does not read it (tests, tools).
    bool forceRsm = false;
    LpvSettings lpv; // Technique::Lpv knobs (vkgi/lpv.hpp)
    // Technique::Vpl (image-space instant radiosity, docs/vpl.md).
    VplSettings vpl;
    VctSettings vct; // Technique::Vct knobs (vkgi/vct.hpp), validated when the technique is created
};

// Checks every setting GiSystem::create checks: the shared ones and those of
// `settings.technique`; the error names the setting, its value and the allowed range. Apps call
// it on the command line's values before any work starts.
Result<void> validateSettings(const GiSettings& settings);

// Which images a frame must produce; everything else is culled by the graph.
struct FrameRequest {
    bool composite = true; // direct + indirect
    bool direct = false;
    bool indirect = false; // only when the technique produces indirect light
    // VCT only (the other techniques leave them empty): the glossy cone's radiance along the
    // mirror direction (nits, before the albedo * metallic weight the indirect image applies;
    // asking for it traces the cone even without metallic materials), and the cone-traced
    // ambient occlusion as visibility 1 - occlusion in [0, 1] in r = g = b (empty with
    // VctSettings::ambientOcclusion off).
    bool glossy = false;
    bool ao = false;
    // GPU timestamps around every pass (FrameResult::passes). Each adds to the frame time on
    // lavapipe (rg::TimestampScopes); off, `passes` is empty and `totalMs` is the frame without
    // the profile's cost.
    bool passTimings = true;
};

// Why a pass of the full pipeline is not in a frame (FrameResult::leftOut).
enum class LeftOutReason : uint32_t {
    Culled,    // registered, but the render graph culled it: nothing requested reads its output
    NotNeeded, // never registered: the scene or the request lacks what it serves (detail says what)
    NotDirty,  // never registered: its persistent result from an earlier frame is still valid
};
// "culled", "not-needed", "not-dirty"
const char* toString(LeftOutReason reason);

struct LeftOutPass {
    std::string name;   // pass name, or a group ("gi.vct.mip[*]", "gi.light[*].point")
    LeftOutReason reason = LeftOutReason::Culled;
    std::string detail; // the scene property, request or change that decided it
};

// Device memory the GiSystem keeps between frames, by owner; the sum is FrameResult::persistentBytes.
struct PersistentMemory {
    uint64_t scene = 0;     // vertex/index/material buffers
    uint64_t shadows = 0;   // shadow-map / RSM atlas
    uint64_t readback = 0;  // host-visible result buffers
    uint64_t technique = 0; // the GI technique's volumes (voxel grid and mips, LPV volumes, VPL buffers)
    uint64_t total() const { return scene + shadows + readback + technique; }
};

struct FrameResult {
    HdrImage composite; // linear radiance (nits); empty unless requested
    HdrImage direct;
    HdrImage indirect;
    HdrImage glossy; // FrameRequest::glossy / ao; empty when the technique does not produce them
    HdrImage ao;
    std::vector<rg::PassTiming> passes;  // executed passes in order, GPU milliseconds
    // GPU ms of the whole frame graph, barriers included (rg::RenderGraph::frameMs). On lavapipe
    // this exceeds the sum of `passes`: part of the work completes inside barriers, outside
    // every pass's timestamp scope.
    double totalMs = 0.0;
    std::vector<std::string> culledPasses;
    std::vector<rg::PassMemory> passMemory; // per executed pass: transients created/touched, bytes accessed
    std::vector<LeftOutPass> leftOut;           // culled + not needed + not dirty, with the reason
    std::vector<std::string> transientResources; // graph transients the executed passes used
    std::vector<std::string> persistentResources; // imported persistent resources the executed passes used
    uint64_t transientBytes = 0;  // render-graph transients of this frame
    uint64_t persistentBytes = 0; // scene, shadow/RSM atlases, technique volumes, readback buffers
    PersistentMemory persistentByOwner; // persistentBytes split by owner
};

// One image owned by the host, given to vkgi for one frame (docs/embedding.md). `view` covers
// the whole image (one mip, one layer; depth aspect for depth). `access` is the last access the
// host made to it, which also names its current layout (rg::accessInfo(access).layout, e.g.
// FragmentSampledRead = SHADER_READ_ONLY_OPTIMAL, ColorAttachmentWrite = COLOR_ATTACHMENT_OPTIMAL,
// None = UNDEFINED): the frame's first barrier waits on that access and transitions from it.
// `usage` is the image's creation usage; the frame checks it covers what vkgi does with it.
struct HostImage {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t width = 0;
    uint32_t height = 0;
    VkImageUsageFlags usage = 0;
    rg::Access access = rg::Access::None;
};

// The host's G-buffer, in vkgi's G-buffer conventions (vkgi/frame_data.hpp) at the camera's pixel
// centres, all the same size; the technique computes the indirect light of these surfaces.
struct HostGBuffer {
    // D32_SFLOAT, Camera::projection depth (0 near .. 1 far, 1 = background); usage SAMPLED.
    // Only read when `position` is not given (world positions are reconstructed from it).
    HostImage depth;
    // R16G16B16A16_SFLOAT: xyz unit world normal turned towards the camera, w roughness;
    // usage SAMPLED | STORAGE.
    HostImage normal;
    // R16G16B16A16_SFLOAT: rgb Lambertian albedo in [0, 1], w metallic; usage SAMPLED | STORAGE.
    HostImage albedo;
    // Optional R32G32B32A32_SFLOAT: xyz world position, w = 1 on geometry, 0 = background;
    // usage SAMPLED | STORAGE. VK_NULL_HANDLE: vkgi reconstructs it from `depth`.
    HostImage position;
};

// A frame on the host's G-buffer (renderIndirect).
struct HostFrame {
    HostGBuffer gbuffer;
    // Optional output: receives the indirect radiance (RGB nits, A = 1) after the frame. Format
    // R32G32B32A32_SFLOAT or R16G16B16A16_SFLOAT, the G-buffer's size, usage TRANSFER_DST.
    HostImage indirect;
    // The states renderIndirect leaves the images in (their layouts: rg::accessInfo(..).layout);
    // read accesses only. The G-buffer's: for the host's own lighting passes next.
    rg::Access indirectFinalAccess = rg::Access::FragmentSampledRead;
    rg::Access gbufferFinalAccess = rg::Access::FragmentSampledRead;
    // Also read the indirect light back into FrameResult::indirect.
    bool readback = false;
};

// Graph handles of the requested outputs of addPasses (invalid when not requested).
struct GiOutputs {
    rg::ImageHandle composite; // RGBA32F
    rg::ImageHandle direct;    // RGBA32F
    rg::ImageHandle indirect;  // RGBA32F (technique dependent)
    rg::ImageHandle glossy;    // RGBA32F glossy cone radiance (VCT; FrameRequest::glossy)
    rg::ImageHandle ao;        // RGBA32F whose alpha is the AO visibility (VCT: the indirect image)
};

class GiSystem {
public:
    // Uses `ctx`, which must outlive the system (embedding in a host engine).
    static Result<std::unique_ptr<GiSystem>> create(Context& ctx, const GiSettings& settings = {});
    // Creates and owns a headless device (defaultDeviceBuilder: VKGI_DEVICE picks the device).
    static Result<std::unique_ptr<GiSystem>> createHeadless(const GiSettings& settings = {});
    ~GiSystem();
    GiSystem(const GiSystem&) = delete;
    GiSystem& operator=(const GiSystem&) = delete;

    Context& context();
    const GiSettings& settings() const;
    // Changes the settings at run time (validated first; on an error nothing changes). Rebuilds
    // only what depends on what changed: the technique module (pipelines, volumes) when the
    // technique or its own settings struct changed (waits for the device); the shadow/RSM atlas
    // at the next frame when its size, layer count or RSM need changed. PCF radius and shadow
    // biases apply to the next frame without any rebuild.
    Result<void> setSettings(const GiSettings& settings);

    // Uploads a scene (validated first; the error names the problem). Replaces any previous one.
    Result<void> setScene(const Scene& scene);
    // Moved instances and lights of the scene given to setScene (same meshes, same counts).
    // Marks exactly what changed: a moved instance re-voxelizes (static: the static bake too)
    // and re-renders the shadow maps; a changed light re-renders its shadow map/RSM and relights
    // the technique's volumes. Unchanged content of persistent volumes is reused next frame.
    Result<void> updateScene(const Scene& scene);
    // Marks everything dirty: the next frame recomputes every persistent result.
    void invalidate();

    // Builds, compiles and executes the frame graph, submits, waits, and reads back the
    // requested images together with per-pass GPU times and memory. Sizes 1..16384.
    Result<FrameResult> renderFrame(const Camera& camera, uint32_t width, uint32_t height,
                                    const FrameRequest& request = {});

    // For hosts with their own graph: adds this frame's passes and marks the requested outputs.
    // The host compiles and executes the graph on the Context's queue, with at most two of this
    // GiSystem's frames in flight: frame constants are double-buffered, and persistent resources
    // (shadow/RSM atlases, technique volumes) carry their last access into the next frame's graph,
    // whose barriers then order it after the previous submission on the same queue (vkgi-view runs
    // this way under synchronization validation). setScene waits for idle; updateScene uploads
    // through the same queue behind full barriers, so it is ordered after the frames in flight.
    // The blackboard gets the shared handles (vkgi/frame_data.hpp) for the host's own passes.
    Result<GiOutputs> addPasses(rg::RenderGraph& graph, rg::Blackboard& blackboard, const Camera& camera,
                                uint32_t width, uint32_t height, const FrameRequest& request = {});

    // Host G-buffer path (docs/embedding.md): the technique's indirect light of the host's
    // surfaces. Builds and executes a graph on the system's queue and waits: it imports the host
    // images in their stated access, copies the indirect light into `frame.indirect` (when given)
    // and leaves it in `frame.indirectFinalAccess`, the G-buffer in `frame.gbufferFinalAccess`.
    // The host must have submitted its G-buffer work to the same queue before this call (or
    // waited for it). Needs a technique other than none.
    Result<FrameResult> renderIndirect(const Camera& camera, const HostFrame& frame);
    // The same passes added to a host graph: GiOutputs::indirect is the graph's indirect image
    // (RGBA32F, marked as output), composite and direct are invalid. The host compiles and
    // executes the graph; the G-buffer images must stay valid until the graph has executed. They
    // are left in the graph's last access unless the host exports their handles (GBufferData).
    Result<GiOutputs> addPasses(rg::RenderGraph& graph, rg::Blackboard& blackboard, const Camera& camera,
                                const HostGBuffer& gbuffer);

    // Host command-buffer path (how FidelityFX-style modules integrate): records the indirect
    // light of the host's G-buffer into `cmd`, a primary command buffer the host has begun and
    // submits itself to the Context's queue (or a queue of the same family). The recording has
    // the barriers from the host images' stated accesses, the passes, the copy into
    // `frame.indirect` (required) and the barriers into the final accesses; no submission and no
    // wait. `frame.readback` must be false (renderIndirect reads back). The host images must stay
    // valid until the command buffer completed, and at most two of this system's frames may be in
    // flight: the system keeps what the last two recordings refer to. No per-pass timings.
    Result<void> record(VkCommandBuffer cmd, const Camera& camera, const HostFrame& frame);

    // Scene + atlases + technique state currently allocated, in bytes.
    uint64_t persistentBytes() const;
    PersistentMemory persistentMemory() const;

private:
    struct Impl;
    explicit GiSystem(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m;
};

} // namespace vkgi::gi
