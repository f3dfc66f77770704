#pragma once
// vkgi-view's Dear ImGui layer (Debian's libimgui 1.86: GLFW + Vulkan backends, which draw
// inside a VkRenderPass). The panel is built from the knob table (vkgi/knobs.hpp), so every
// technique setting is editable without UI code per knob. Drawing is one render-graph pass
// that loads the tone-mapped swapchain image and draws the panel over it.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "vkgi/context.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/scene.hpp"
#include "vkgi/gi.hpp"
#include "window.hpp"

namespace vkgi::view {

// What the panel shows and may edit this frame.
struct PanelModel {
    const gi::GiSettings* settings = nullptr;
    Scene* scene = nullptr;                // lights and instances are edited in place
    std::optional<uint32_t> dynamicObject; // instance the object controls move
    bool* animate = nullptr;               // scripted light/object loop on or off
    float* exposure = nullptr;
    const std::vector<rg::PassTiming>* passes = nullptr; // last finished frame
    double gpuMs = 0.0;
    double frameMs = 0.0; // smoothed wall time between presents
    bool flyCamera = false;
    VkExtent2D size{};
    std::string status; // last screenshot / last error
};

// What the user asked for this frame.
struct PanelActions {
    std::optional<gi::GiSettings> settings; // new technique or knob value: rebuild the GiSystem
    bool sceneEdited = false;               // a light or the object moved: GiSystem::updateScene
    bool screenshot = false;
    bool resetCamera = false;
    bool toggleCamera = false;
};

class Ui {
public:
    // `framesInFlight` sizes ImGui's per-frame vertex buffers (each is rewritten by the CPU).
    static Result<std::unique_ptr<Ui>> create(Context& ctx, const Window& window, uint32_t framesInFlight);
    ~Ui();
    Ui(const Ui&) = delete;
    Ui& operator=(const Ui&) = delete;

    // Framebuffers of the (re)created swapchain; the device must be idle.
    void setTargets(const Swapchain& swapchain);
    // Starts an ImGui frame, builds the panel (when visible) and ends the frame.
    PanelActions build(PanelModel& model);
    void toggleVisible() { m_visible = !m_visible; }
    bool wantsMouse() const;
    bool wantsKeyboard() const;
    // Draws the panel over `target` (swapchain image `imageIndex`); returns the new version.
    rg::ImageHandle addPass(rg::RenderGraph& graph, rg::ImageHandle target, uint32_t imageIndex);

private:
    explicit Ui(Context& ctx) : m_ctx(ctx) {}
    void destroyFramebuffers();
    bool knobControls(gi::GiSettings& edited);
    bool sceneControls(PanelModel& model);
    Context& m_ctx;
    VkDescriptorPool m_pool = VK_NULL_HANDLE;
    VkRenderPass m_renderPass = VK_NULL_HANDLE;
    std::vector<VkFramebuffer> m_framebuffers;
    VkExtent2D m_extent{};
    bool m_backendsReady = false;
    bool m_visible = true;
    int m_selectedLight = 0;
    std::string m_knobError;
};

} // namespace vkgi::view
