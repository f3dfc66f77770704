#pragma once
// vkgi's public GI API. A GiSystem renders a scene with direct lighting (G-buffer, shadow maps,
// deferred shading) plus the indirect light of the selected technique, either as a whole
// frame (renderFrame: build graph, execute, submit, wait, read back) or as passes added to a
// host's own render graph (addPasses). Every pass goes through vkgi::rg, so unrequested work
// is culled and every pass is timed.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "engine/camera.hpp"
#include "engine/context.hpp"
#include "engine/hdr_image.hpp"
#include "engine/result.hpp"
#include "engine/rg/blackboard.hpp"
#include "engine/rg/render_graph.hpp"
#include "engine/scene.hpp"
#include "gi/lpv.hpp"
#include "gi/vpl.hpp"
#include "gi/vct.hpp"

namespace vkgi::gi {

// The indirect-light technique. None = direct lighting (+ emission) only.
enum class Technique : uint32_t { None = 0, Lpv = 1, Vct = 2, Vpl = 3 };

// "none", ...; the names the CLI accepts.
const char* toString(Technique technique);
std::vector<std::string> techniqueNames();
// Reflections between emitter and eye the technique models with default settings (none: 1 =
// direct light only; one indirect bounce: 2): the path-tracer bounce count to compare against.
int modelledBounces(Technique technique);
// Parses a name from techniqueNames(); the error lists the valid names.
Result<Technique> parseTechnique(std::string_view name);

struct GiSettings {
    Technique technique = Technique::None;
    // Texels per side of each shadow-map (and RSM) layer: 256 keeps a cube light's RSM at
    // 15.7 MiB (40 B/texel x 6 x 256^2), inside the 64 MiB module budget.
    uint32_t shadowMapSize = 256;
    // Atlas layers (a spot/directional light takes 1, a point light or wide spot 6); lights past
    // the limit are unshadowed. 64 layers of 256^2 D32 = 16 MiB.
    uint32_t maxShadowLayers = 64;
    // PCF kernel (2r+1)^2 of bilinear compares; 1 = 3x3 softens the 1-texel stair steps.
    uint32_t pcfRadius = 1;
    // Shadow biases in shadow-texel world sizes at the receiver: a normal offset and a depth
    // bias below the receiver's tangent plane, which every PCF texel is compared against
    // (deferred.comp), so no slope-scaled term is needed.
    float shadowNormalOffset = 0.0f;
    float shadowConstantBias = 0.5f;
    // Render the reflective shadow map even when the technique does not read it (tests, tools).
    bool forceRsm = false;
    LpvSettings lpv; // Technique::Lpv knobs (gi/lpv.hpp)
    // Technique::Vpl (image-space instant radiosity, docs/vpl.md).
    VplSettings vpl;
    VctSettings vct; // Technique::Vct knobs (gi/vct.hpp), validated when the technique is created
};

// Which images a frame must produce; everything else is culled by the graph.
struct FrameRequest {
    bool composite = true; // direct + indirect
    bool direct = false;
    bool indirect = false; // only when the technique produces indirect light
};

struct FrameResult {
    HdrImage composite; // linear radiance (nits); empty unless requested
    HdrImage direct;
    HdrImage indirect;
    std::vector<rg::PassTiming> passes;  // executed passes in order, GPU milliseconds
    double totalMs = 0.0;                // sum of `passes`
    std::vector<std::string> culledPasses;
    std::vector<rg::PassMemory> passMemory; // per executed pass: transients created/touched, bytes accessed
    uint64_t transientBytes = 0;  // render-graph transients of this frame
    uint64_t persistentBytes = 0; // scene, shadow/RSM atlases, technique volumes, readback buffers
};

// Graph handles of the requested outputs of addPasses (invalid when not requested).
struct GiOutputs {
    rg::ImageHandle composite; // RGBA32F
    rg::ImageHandle direct;    // RGBA32F
    rg::ImageHandle indirect;  // RGBA32F (technique dependent)
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

    // Uploads a scene (validated first; the error names the problem). Replaces any previous one.
    Result<void> setScene(const Scene& scene);
    // Moved instances and lights of the scene given to setScene (same meshes, same counts).
    Result<void> updateScene(const Scene& scene);

    // Builds, compiles and executes the frame graph, submits, waits, and reads back the
    // requested images together with per-pass GPU times and memory. Sizes 1..16384.
    Result<FrameResult> renderFrame(const Camera& camera, uint32_t width, uint32_t height,
                                    const FrameRequest& request = {});

    // For hosts with their own graph: adds this frame's passes and marks the requested outputs.
    // The host compiles and executes the graph and must keep this GiSystem's previous frame
    // finished before calling again (shadow/RSM atlases are persistent). The blackboard gets
    // the shared handles (gi/frame_data.hpp) for the host's own passes.
    Result<GiOutputs> addPasses(rg::RenderGraph& graph, rg::Blackboard& blackboard, const Camera& camera,
                                uint32_t width, uint32_t height, const FrameRequest& request = {});

    // Scene + atlases + technique state currently allocated, in bytes.
    uint64_t persistentBytes() const;

private:
    struct Impl;
    explicit GiSystem(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m;
};

} // namespace vkgi::gi
