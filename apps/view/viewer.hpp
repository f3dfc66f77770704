#pragma once
// vkgi-view's frame loop: GiSystem passes + tone map + ImGui in one render graph per frame,
// recorded into one of two frame slots so the CPU builds frame N+1 while the GPU renders N.
// Two frames in flight is what GiSystem's FrameConstants ring (2 entries) and the transient
// pool (entries idle for 8 executions survive) are sized for; GPU-side hazards between
// frames are covered by the graph's barriers, derived from the states it carries over (on
// the one queue). GiSystem frees persistent images only on a settings or scene change: the
// viewer waits for both slots before those (setSettings, updateScene), and the shadow atlas
// waits for the device itself when its layout changes.
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vkgi/context.hpp"
#include "vkgi/pipeline.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/rg/transient_pool.hpp"
#include "vkgi/scene.hpp"
#include "vkgi/gi.hpp"
#include "motion.hpp"
#include "options.hpp"
#include "ui.hpp"
#include "window.hpp"

namespace vkgi::view {

class Viewer {
public:
    static constexpr uint32_t kFramesInFlight = 2;

    static Result<std::unique_ptr<Viewer>> create(const Options& options, Window& window, Context& ctx, Scene scene,
                                                  const gi::GiSettings& settings);
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    // Runs until the window closes (or the scripted frames end with --exit). Exit code.
    int run();

private:
    struct FrameSlot {
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        VkFence fence = VK_NULL_HANDLE; // signalled when the slot's last submit finished
        VkSemaphore acquired = VK_NULL_HANDLE;
        std::unique_ptr<TimestampPool> timestamps;
        std::unique_ptr<rg::RenderGraph> graph; // kept until the fence: its pass timings
        Buffer readback;                        // screenshot of this slot's composite
        std::optional<std::filesystem::path> screenshot;
        VkExtent2D size{};
        bool submitted = false;
    };

    Viewer(const Options& options, Window& window, Context& ctx) : m_options(options), m_window(window), m_ctx(ctx) {}
    Result<void> init(Scene scene, const gi::GiSettings& settings);
    // Waits for a slot's submit and takes its results (timings, screenshot files).
    Result<void> finish(FrameSlot& slot);
    Result<void> finishAll();
    Result<void> createGi(const gi::GiSettings& settings);
    Result<void> recreateSwapchain();
    void handleKeys(const std::vector<int>& keys, bool& screenshot, std::optional<gi::GiSettings>& settings);
    // Keys, the scripted technique switch and the panel: rebuilds the GiSystem or updates the
    // scene as asked. True when a screenshot was asked for.
    Result<bool> applyEdits(const std::vector<int>& keys, bool scriptedFrame, float t);
    void printSummary() const;
    CameraInput cameraInput(double scroll, float dt);
    Result<void> updateScene(float t);
    Result<void> record(FrameSlot& slot, uint32_t imageIndex, const Camera& camera);
    std::filesystem::path nextScreenshotPath() const;

    const Options& m_options;
    Window& m_window;
    Context& m_ctx;
    std::unique_ptr<Swapchain> m_swapchain;
    std::unique_ptr<Ui> m_ui;
    std::unique_ptr<rg::TransientPool> m_pool;
    std::unique_ptr<gi::GiSystem> m_gi;
    Pipeline m_tonemap;
    VkCommandPool m_commandPool = VK_NULL_HANDLE;
    FrameSlot m_slots[kFramesInFlight];
    uint64_t m_frame = 0;

    Scene m_scene;    // as edited in the panel
    Scene m_uploaded; // what GiSystem has (m_scene, animated)
    std::optional<uint32_t> m_object;
    bool m_animate = false;
    float m_exposure = 1.0f;
    std::optional<CameraController> m_camera;
    std::optional<CameraScript> m_script;

    std::vector<rg::PassTiming> m_passes; // last finished frame
    double m_gpuMs = 0.0;
    double m_frameMs = 0.0;
    std::vector<double> m_frameTimes; // wall ms of every frame, for the exit summary
    std::vector<double> m_gpuTimes;
    std::string m_status;
    bool m_swapchainStale = false;
    bool m_resized = false; // the scripted --resize-at happened
    double m_cursor[2] = {0.0, 0.0};
    std::chrono::steady_clock::time_point m_start;
};

} // namespace vkgi::view
