#include "viewer.hpp"

#include <algorithm>
#include <cstdio>

#include <GLFW/glfw3.h>

#include "vkgi/image_io.hpp"
#include "vkgi/rg/compute_pass.hpp"
#include "vk_check.hpp"
#include "vkgi/knobs.hpp"
#include "view/tonemap_bindings.h"

namespace vkgi::view {

namespace {

// Push constants of shaders/view/tonemap.comp.
struct TonemapPush {
    glm::uvec4 size;  // swapchain w, h; composite w, h
    glm::vec4 params; // exposure, 1 = ACES
};

// Frames left out of the exit summary: the first ones pay lavapipe's shader JIT.
constexpr size_t kWarmupFrames = 3;

double median(std::vector<double> v) {
    if (v.empty())
        return 0.0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

HdrImage toHdr(const Buffer& rgba32f, VkExtent2D size) {
    HdrImage image(size.width, size.height);
    const auto* texels = static_cast<const glm::vec4*>(rgba32f.mapped());
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = glm::vec3(texels[i]);
    return image;
}

} // namespace

Result<std::unique_ptr<Viewer>> Viewer::create(const Options& options, Window& window, Context& ctx, Scene scene,
                                               const gi::GiSettings& settings) {
    std::unique_ptr<Viewer> v(new Viewer(options, window, ctx));
    if (auto ok = v->init(std::move(scene), settings); !ok)
        return ok.error();
    return v;
}

Result<void> Viewer::init(Scene scene, const gi::GiSettings& settings) {
    m_exposure = m_options.exposure;
    m_animate = m_options.animate;
    m_object = SceneAnimation::pickDynamicInstance(scene);
    if (m_object)
        scene.instances[*m_object].dynamic = true;
    m_scene = scene;
    m_uploaded = scene;
    Camera start = scene.cameraOrDefault();
    m_camera.emplace(start, scene.bounds());
    auto script = CameraScript::load(m_options.cameraScript, start, scene.bounds());
    if (!script)
        return script.error();
    m_script = *script;

    auto surface = m_window.createSurface(m_ctx.instance());
    if (!surface)
        return surface.error();
    auto swapchain = Swapchain::create(m_ctx, *surface, m_options.present, m_options.width, m_options.height);
    if (!swapchain)
        return swapchain.error();
    m_swapchain = std::move(*swapchain);
    if (m_options.ui) {
        auto ui = Ui::create(m_ctx, m_window, kFramesInFlight);
        if (!ui)
            return ui.error();
        m_ui = std::move(*ui);
        m_ui->setTargets(*m_swapchain);
    }
    auto tonemap = createComputePipeline(m_ctx, {"view/tonemap.comp", {}});
    if (!tonemap)
        return tonemap.error();
    m_tonemap = std::move(*tonemap);
    m_pool = std::make_unique<rg::TransientPool>(m_ctx);

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = m_ctx.queueFamily();
    VKGI_CHECK(vkCreateCommandPool(m_ctx.device(), &poolInfo, nullptr, &m_commandPool));
    for (FrameSlot& slot : m_slots) {
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = m_commandPool;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        VKGI_CHECK(vkAllocateCommandBuffers(m_ctx.device(), &alloc, &slot.cmd));
        VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
        VKGI_CHECK(vkCreateFence(m_ctx.device(), &fence, nullptr, &slot.fence));
        VkSemaphoreCreateInfo sem{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VKGI_CHECK(vkCreateSemaphore(m_ctx.device(), &sem, nullptr, &slot.acquired));
        if (m_ctx.timestampsSupported())
            slot.timestamps = std::make_unique<TimestampPool>(m_ctx, 512);
    }
    return createGi(settings);
}

Viewer::~Viewer() {
    vkDeviceWaitIdle(m_ctx.device());
    for (FrameSlot& slot : m_slots) {
        slot.graph.reset();
        slot.timestamps.reset();
        if (slot.readback)
            destroyBuffer(m_ctx, slot.readback);
        if (slot.fence)
            vkDestroyFence(m_ctx.device(), slot.fence, nullptr);
        if (slot.acquired)
            vkDestroySemaphore(m_ctx.device(), slot.acquired, nullptr);
    }
    if (m_commandPool)
        vkDestroyCommandPool(m_ctx.device(), m_commandPool, nullptr);
    m_gi.reset();
    m_pool.reset();
    if (m_tonemap.pipeline)
        destroyPipeline(m_ctx, m_tonemap);
    m_ui.reset();
    m_swapchain.reset();
}

Result<void> Viewer::finish(FrameSlot& slot) {
    VKGI_CHECK(vkWaitForFences(m_ctx.device(), 1, &slot.fence, VK_TRUE, UINT64_MAX));
    if (!slot.submitted)
        return {};
    slot.submitted = false;
    m_passes = slot.graph->timings();
    m_gpuMs = 0.0;
    for (const rg::PassTiming& p : m_passes)
        m_gpuMs += p.ms;
    m_gpuTimes.push_back(m_gpuMs);
    if (!slot.screenshot)
        return {};
    std::filesystem::path exr = *slot.screenshot;
    std::filesystem::path png = std::filesystem::path(exr).replace_extension(".png");
    slot.screenshot.reset();
    HdrImage image = toHdr(slot.readback, slot.size);
    std::error_code ec;
    if (exr.has_parent_path())
        std::filesystem::create_directories(exr.parent_path(), ec);
    if (auto ok = writeExr(exr, image); !ok)
        return ok.error();
    if (auto ok = writePng(png, image, ToneMap{m_exposure, ToneMap::Curve::Aces}); !ok)
        return ok.error();
    m_status = "wrote " + exr.string() + " + .png";
    std::printf("vkgi-view: wrote %s and %s\n", exr.string().c_str(), png.string().c_str());
    return {};
}

Result<void> Viewer::finishAll() {
    for (FrameSlot& slot : m_slots)
        if (auto ok = finish(slot); !ok)
            return ok;
    return {};
}

Result<void> Viewer::createGi(const gi::GiSettings& settings) {
    if (auto ok = finishAll(); !ok)
        return ok;
    m_gi.reset();
    auto system = gi::GiSystem::create(m_ctx, settings);
    if (!system)
        return system.error();
    if (auto ok = (*system)->setScene(m_uploaded); !ok)
        return ok.error();
    m_gi = std::move(*system);
    std::printf("vkgi-view: technique %s (%s)\n", gi::toString(settings.technique),
                gi::describeKnobs(settings).c_str());
    return {};
}

Result<void> Viewer::recreateSwapchain() {
    uint32_t w = 0, h = 0;
    m_window.framebufferSize(w, h);
    if (auto ok = finishAll(); !ok)
        return ok;
    VKGI_CHECK(vkDeviceWaitIdle(m_ctx.device())); // presentation may still hold the old images
    if (auto ok = m_swapchain->recreate(w, h); !ok)
        return ok;
    if (m_ui)
        m_ui->setTargets(*m_swapchain);
    m_swapchainStale = false;
    return {};
}

Result<void> Viewer::updateScene(float t) {
    // updateScene rewrites buffers the frames in flight read: wait for them first.
    if (auto ok = finishAll(); !ok)
        return ok;
    m_uploaded = m_animate ? SceneAnimation::at(m_scene, m_object, t) : m_scene;
    return m_gi->updateScene(m_uploaded);
}

std::filesystem::path Viewer::nextScreenshotPath() const {
    std::string stem = "vkgi-view-" + std::filesystem::path(m_options.scene).stem().string() + "-" +
                       gi::toString(m_gi->settings().technique) + "-";
    for (int n = 1;; ++n) {
        std::filesystem::path p = stem + std::to_string(n) + ".exr";
        if (!std::filesystem::exists(p))
            return p;
    }
}

void Viewer::handleKeys(const std::vector<int>& keys, bool& screenshot, std::optional<gi::GiSettings>& settings) {
    std::vector<std::string> names = gi::techniqueNames();
    for (int key : keys) {
        if (key == GLFW_KEY_ESCAPE)
            m_window.requestClose();
        else if (key == GLFW_KEY_TAB)
            m_camera->toggleMode();
        else if (key == GLFW_KEY_R)
            m_camera->reset();
        else if (key == GLFW_KEY_H && m_ui)
            m_ui->toggleVisible();
        else if (key == GLFW_KEY_F12 || key == GLFW_KEY_P)
            screenshot = true;
        else if (key >= GLFW_KEY_1 && key < GLFW_KEY_1 + int(names.size())) {
            gi::GiSettings s = settings.value_or(m_gi->settings());
            s.technique = *gi::parseTechnique(names[size_t(key - GLFW_KEY_1)]);
            if (s.technique != m_gi->settings().technique)
                settings = s;
        }
    }
}

CameraInput Viewer::cameraInput(double scroll, float dt) {
    GLFWwindow* w = m_window.handle();
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(w, &x, &y);
    glm::vec2 delta(float(x - m_cursor[0]), float(y - m_cursor[1]));
    m_cursor[0] = x;
    m_cursor[1] = y;
    CameraInput in;
    in.dt = dt;
    if (!(m_ui && m_ui->wantsMouse())) {
        if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS)
            in.dragLeft = delta;
        if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS)
            in.dragRight = delta;
        in.scroll = float(scroll);
    }
    if (!(m_ui && m_ui->wantsKeyboard())) {
        auto down = [&](int key) { return glfwGetKey(w, key) == GLFW_PRESS ? 1.0f : 0.0f; };
        in.move = {down(GLFW_KEY_D) - down(GLFW_KEY_A), down(GLFW_KEY_E) - down(GLFW_KEY_Q),
                   down(GLFW_KEY_W) - down(GLFW_KEY_S)};
        in.fast = down(GLFW_KEY_LEFT_SHIFT) > 0.0f || down(GLFW_KEY_RIGHT_SHIFT) > 0.0f;
    }
    return in;
}

Result<void> Viewer::record(FrameSlot& slot, uint32_t imageIndex, const Camera& camera) {
    VkExtent2D size = m_swapchain->extent();
    slot.graph = std::make_unique<rg::RenderGraph>();
    rg::RenderGraph& graph = *slot.graph;
    rg::Blackboard blackboard;
    auto outputs = m_gi->addPasses(graph, blackboard, camera, size.width, size.height);
    if (!outputs)
        return outputs.error();
    rg::ImageHandle composite = outputs->composite;
    rg::ImageHandle target = graph.importImage("view.swapchain", m_swapchain->image(imageIndex), rg::Access::Present);

    TonemapPush push{{size.width, size.height, size.width, size.height}, {m_exposure, 1.0f, 0.0f, 0.0f}};
    rg::ComputePass(graph, "view.tonemap", m_tonemap)
        .push(push)
        .read(VIEW_TONEMAP_BINDING_COMPOSITE, composite)
        .overwrite(VIEW_TONEMAP_BINDING_TARGET, target)
        .dispatch({size.width, size.height, 1});
    if (m_ui)
        target = m_ui->addPass(graph, target, imageIndex);
    graph.exportImage(target, rg::Access::Present);

    if (slot.screenshot) {
        VkDeviceSize bytes = VkDeviceSize(size.width) * size.height * sizeof(glm::vec4);
        if (!slot.readback || slot.readback.desc.size != bytes) {
            if (slot.readback)
                destroyBuffer(m_ctx, slot.readback);
            slot.readback = createBuffer(m_ctx, {bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::GpuToCpu},
                                         "view.screenshot");
        }
        slot.size = size;
        rg::BufferHandle buffer = graph.importBuffer("view.screenshot", slot.readback, rg::Access::None);
        graph.addPass(
            "view.screenshot",
            [&](rg::PassBuilder& b) {
                b.read(composite, rg::Access::TransferRead);
                buffer = b.write(buffer, rg::Access::TransferWrite);
            },
            [=](rg::PassContext& pc) {
                VkBufferImageCopy region{};
                region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                region.imageExtent = {size.width, size.height, 1};
                vkCmdCopyImageToBuffer(pc.cmd(), pc.image(composite).image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                       pc.buffer(buffer).buffer, 1, &region);
            });
        graph.exportBuffer(buffer, rg::Access::HostRead);
    }
    if (auto ok = graph.compile(); !ok)
        return makeError("frame graph: " + ok.error().message);

    VKGI_CHECK(vkResetCommandBuffer(slot.cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VKGI_CHECK(vkBeginCommandBuffer(slot.cmd, &begin));
    graph.execute(slot.cmd, m_ctx, *m_pool, slot.timestamps.get());
    VKGI_CHECK(vkEndCommandBuffer(slot.cmd));

    VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    wait.semaphore = slot.acquired;
    wait.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT; // the graph's first swapchain barrier waits on all stages
    VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    signal.semaphore = m_swapchain->renderFinished(imageIndex);
    signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cmdInfo.commandBuffer = slot.cmd;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.waitSemaphoreInfoCount = 1;
    submit.pWaitSemaphoreInfos = &wait;
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cmdInfo;
    submit.signalSemaphoreInfoCount = 1;
    submit.pSignalSemaphoreInfos = &signal;
    VKGI_CHECK(vkResetFences(m_ctx.device(), 1, &slot.fence));
    VKGI_CHECK(vkQueueSubmit2(m_ctx.queue(), 1, &submit, slot.fence));
    slot.submitted = true;
    return {};
}

int Viewer::run() {
    const uint32_t scripted = m_options.frames.value_or(0);
    auto fail = [](const Error& e) {
        std::fprintf(stderr, "vkgi-view: %s\n", e.message.c_str());
        return 1;
    };
    glfwGetCursorPos(m_window.handle(), &m_cursor[0], &m_cursor[1]);
    m_start = std::chrono::steady_clock::now();
    auto last = m_start;
    while (!m_window.shouldClose()) {
        if (m_options.resizeFrame && m_frame == *m_options.resizeFrame && !m_resized) {
            m_window.resize(m_options.resizeWidth, m_options.resizeHeight);
            m_resized = true;
        }
        glfwPollEvents();
        WindowEvents events = m_window.takeEvents();
        uint32_t fw = 0, fh = 0;
        m_window.framebufferSize(fw, fh);
        if (fw == 0 || fh == 0) { // minimised: nothing to present until restored
            glfwWaitEvents();
            continue;
        }
        VkExtent2D extent = m_swapchain->extent();
        if (events.resized || m_swapchainStale || extent.width != fw || extent.height != fh)
            if (auto ok = recreateSwapchain(); !ok)
                return fail(ok.error());

        const bool scriptedFrame = m_frame < scripted;
        const float t = scriptedFrame ? (scripted > 1 ? float(m_frame) / float(scripted - 1) : 1.0f)
                                      : float(std::chrono::duration<double>(last - m_start).count() * 0.1);
        FrameSlot& slot = m_slots[m_frame % kFramesInFlight];
        if (auto ok = finish(slot); !ok)
            return fail(ok.error());

        uint32_t imageIndex = m_swapchain->acquire(slot.acquired);
        if (imageIndex == Swapchain::kNoImage) {
            m_swapchainStale = true;
            continue;
        }

        auto now = std::chrono::steady_clock::now();
        double ms = std::chrono::duration<double, std::milli>(now - last).count();
        float dt = float(ms / 1000.0);
        last = now;
        if (m_frame > 0) {
            m_frameTimes.push_back(ms);
            m_frameMs = m_frameMs == 0.0 ? ms : 0.9 * m_frameMs + 0.1 * ms;
        }

        auto screenshot = applyEdits(events.keysPressed, scriptedFrame, t);
        if (!screenshot)
            return fail(screenshot.error());

        if (scriptedFrame)
            m_camera->setCamera(m_script->at(t));
        else
            m_camera->update(cameraInput(events.scrollY, dt));

        if (scriptedFrame && m_frame + 1 == scripted && m_options.screenshot)
            slot.screenshot = *m_options.screenshot;
        else if (*screenshot)
            slot.screenshot = nextScreenshotPath();
        if (auto ok = record(slot, imageIndex, m_camera->camera()); !ok)
            return fail(ok.error());
        if (!m_swapchain->present(imageIndex))
            m_swapchainStale = true;
        ++m_frame;
        if (m_options.exitAfterFrames && m_frame >= scripted)
            break;
    }
    if (auto ok = finishAll(); !ok)
        return fail(ok.error());
    if (m_options.exitAfterFrames && m_frame < scripted)
        return fail(makeError("the window was closed after " + std::to_string(m_frame) + " of " +
                              std::to_string(scripted) + " scripted frames"));
    printSummary();
    return 0;
}

Result<bool> Viewer::applyEdits(const std::vector<int>& keys, bool scriptedFrame, float t) {
    bool screenshot = false;
    std::optional<gi::GiSettings> newSettings;
    handleKeys(keys, screenshot, newSettings);
    if (scriptedFrame && m_options.switchFrame && m_frame == *m_options.switchFrame) {
        gi::GiSettings s = m_gi->settings();
        s.technique = *gi::parseTechnique(m_options.switchTechnique);
        newSettings = s;
    }
    bool sceneEdited = false;
    if (m_ui) {
        PanelModel model;
        model.settings = &m_gi->settings();
        model.scene = &m_scene;
        model.dynamicObject = m_object;
        model.animate = &m_animate;
        model.exposure = &m_exposure;
        model.passes = &m_passes;
        model.gpuMs = m_gpuMs;
        model.frameMs = m_frameMs;
        model.flyCamera = m_camera->mode() == CameraController::Mode::Fly;
        model.size = m_swapchain->extent();
        model.status = m_status;
        PanelActions actions = m_ui->build(model);
        screenshot |= actions.screenshot;
        sceneEdited = actions.sceneEdited;
        if (actions.settings)
            newSettings = actions.settings;
        if (actions.resetCamera)
            m_camera->reset();
        if (actions.toggleCamera)
            m_camera->toggleMode();
    }
    if (newSettings) {
        // The system rebuilds only what the changed knobs feed; wrong settings change nothing.
        if (auto ok = finishAll(); !ok)
            return ok.error();
        if (auto ok = m_gi->setSettings(*newSettings); !ok) {
            m_status = ok.error().message; // the panel shows it; the previous settings stay
            std::fprintf(stderr, "vkgi-view: %s\n", ok.error().message.c_str());
        } else {
            std::printf("vkgi-view: technique %s (%s)\n", gi::toString(newSettings->technique),
                        gi::describeKnobs(*newSettings).c_str());
        }
    }
    if (sceneEdited || m_animate)
        if (auto ok = updateScene(t); !ok)
            return ok.error();
    return screenshot;
}

void Viewer::printSummary() const {
    if (m_frameTimes.size() <= kWarmupFrames || m_gpuTimes.size() <= kWarmupFrames)
        return;
    std::vector<double> frames(m_frameTimes.begin() + kWarmupFrames, m_frameTimes.end());
    std::vector<double> gpu(m_gpuTimes.begin() + kWarmupFrames, m_gpuTimes.end());
    VkExtent2D e = m_swapchain->extent();
    std::string own; // the viewer's own passes in the last frame
    char ms[32];
    for (const rg::PassTiming& p : m_passes)
        if (p.name.rfind("view.", 0) == 0) {
            std::snprintf(ms, sizeof(ms), " %.3f ms", p.ms);
            own += " " + p.name + ms;
        }
    std::printf("vkgi-view: %zu frames at %ux%u (%s, present %s): median frame %.2f ms, median GPU %.2f ms "
                "(first %zu frames left out); last frame:%s\n",
                m_frameTimes.size() + 1, e.width, e.height, gi::toString(m_gi->settings().technique),
                m_swapchain->presentModeName(), median(frames), median(gpu), kWarmupFrames, own.c_str());
}

} // namespace vkgi::view
