#pragma once
// Pass selection: what a frame needs, from the scene, the request and what changed since the
// last frame. GiSystem registers only the passes this says are needed and records every pass of
// the full pipeline it leaves out, with the reason (FrameResult::leftOut); the render graph then
// culls what no requested output reads.
//
// Three reasons a pass is absent:
//   not needed   the scene or request lacks what the pass serves: no light of a kind (no shadow
//                or RSM pass for it), no spotlight (VPL), no emissive material (no emission
//                injection into the voxels), no metallic material (no glossy cone: the trace
//                weights it by metallic), technique none (no voxel grid or LPV is ever
//                allocated), a request without composite/indirect (no technique pass at all).
//   not dirty    its result is a persistent graph resource that is still valid: shadow/RSM layers
//                of unchanged lights, the voxel grid (static bake and dynamic objects), the VCT
//                voxel light, mips and bounce, the LPV injection and propagation.
//   culled       registered, but the graph found no requested output reading it.
//
// Dirty tracking (SceneChanges): setScene and invalidate() dirty everything; updateScene marks
// exactly the instances and lights whose transform or parameters changed. Camera motion alone
// dirties nothing view-independent. LPV is the exception by design: its geometry volume takes
// the camera's G-buffer surfels as well as the RSM's (view dependent), and its cascades follow
// the camera, so with occlusion on (or cascades > 1 under a directional light) a camera change
// re-runs injection and propagation; otherwise LPV reuses the propagated volume too.
#include <cstdint>
#include <string>
#include <vector>

#include "vkgi/camera.hpp"
#include "vkgi/scene.hpp"
#include "vkgi/gi.hpp"

namespace vkgi::gi {

// What the scene contains, as far as pass selection cares. Only instanced meshes count.
struct SceneFeatures {
    uint32_t directionalLights = 0;
    uint32_t pointLights = 0;
    uint32_t spotLights = 0;
    bool emissive = false;       // an instanced material with emission > 0
    bool metallic = false;       // an instanced material with metallic > 0 (the glossy cone's weight)
    bool dynamicObjects = false; // an instance with dynamic = true
    bool geometry = false;       // at least one instanced triangle
    uint32_t lights() const { return directionalLights + pointLights + spotLights; }
};
SceneFeatures analyzeScene(const Scene& scene);

// What changed since a consumer (the shadow passes, the technique) last registered its passes.
struct SceneChanges {
    bool all = true;              // first frame, new scene, new shadow targets, or invalidate()
    bool staticGeometry = false;  // a static instance moved
    bool dynamicGeometry = false; // a dynamic instance moved
    bool camera = false;          // camera or frame size differs from the consumer's last frame
    std::vector<uint32_t> lights; // changed lights (indices into Scene::lights), ascending

    bool geometry() const { return all || staticGeometry || dynamicGeometry; }
    bool lightChanged(uint32_t light) const;
    bool anyLight() const { return all || !lights.empty(); }
    // Anything view-independent changed.
    bool any() const { return all || staticGeometry || dynamicGeometry || !lights.empty(); }
    // Adds `other` (accumulating edits until the consumer runs).
    void merge(const SceneChanges& other);
    void reset() { *this = SceneChanges{false}; }
};

// The changes between two versions of the same scene (updateScene: same meshes, same counts).
SceneChanges diffScenes(const Scene& before, const Scene& after);

// Blackboard entry GiSystem adds before any pass: technique modules read the scene's features
// and the changes since their last frame, and record each pass they leave out.
struct PassSelection {
    SceneFeatures features;
    SceneChanges changes; // since the technique's last registered frame
    std::vector<LeftOutPass> leftOut;
    FrameRequest request; // the frame's requested outputs

    void leaveOut(std::string name, LeftOutReason reason, std::string detail) {
        leftOut.push_back({std::move(name), reason, std::move(detail)});
    }
};

// "light 2 moved", "object 3 moved", "no light or object changed", ... for NotDirty details.
std::string describeChanges(const SceneChanges& changes);

struct ShadowLayout;
// Shadow/RSM passes to leave out: per light, true when its atlas (and RSM) layers still hold this
// frame's content: same layers, bitwise same views as in `last` (the layout the persistent atlas
// was last rendered with; empty = never) and no change to the light or to any object since.
std::vector<bool> cleanShadowLights(const ShadowLayout& now, const ShadowLayout& last, const SceneChanges& changes);

// RSM window passes to leave out: per light, true when its RSM layer still holds this frame's
// window (LightShadowPlan::rsmView): windowed then and now, the same layer and bitwise the same
// view, no change to the light or to any object. Independent of the light's own layer, which
// a moved window leaves as it is.
std::vector<bool> cleanRsmWindows(const ShadowLayout& now, const ShadowLayout& last, const SceneChanges& changes);

// Cascade passes to leave out: per light, bit k set when its cascade k still holds this frame's
// content: same layers, a bitwise same view (the camera moved less than that cascade's texel, or
// not at all), and no change to the light or to any object since.
std::vector<uint32_t> cleanShadowCascades(const ShadowLayout& now, const ShadowLayout& last, const SceneChanges& changes);

// Shadow-window passes to leave out: per light, bit k set when its window layer k still holds
// this frame's content: same layers, a bitwise same view (the window's box did not move) and no
// change to the light or to any object since.
std::vector<uint32_t> cleanShadowWindows(const ShadowLayout& now, const ShadowLayout& last, const SceneChanges& changes);

// Same camera and frame size (bitwise): view-dependent work may be reused.
bool sameView(const Camera& a, uint32_t aw, uint32_t ah, const Camera& b, uint32_t bw, uint32_t bh);

// Left-out entries for light kinds the scene does not have ("gi.light[*].point": no point light).
void leaveOutMissingLightKinds(const SceneFeatures& features, PassSelection& selection);

} // namespace vkgi::gi
