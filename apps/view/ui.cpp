#include "ui.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include "vk_check.hpp"
#include "vkgi/knobs.hpp"

namespace vkgi::view {

namespace {

void checkVk(VkResult r) {
    VKGI_CHECK(r);
}

// The panel's value of a knob (Knob::get gives text: "64", "0.25", "on"/"off").
double knobValue(const gi::Knob& knob, const gi::GiSettings& s) {
    std::string text = knob.get(s);
    if (knob.kind == gi::Knob::Kind::Bool)
        return (text == "on" || text == "true" || text == "1") ? 1.0 : 0.0;
    if (knob.kind == gi::Knob::Kind::Enum) {
        for (size_t i = 0; i < knob.choices.size(); ++i)
            if (knob.choices[i] == text)
                return double(i);
        return 0.0;
    }
    return std::strtod(text.c_str(), nullptr);
}

std::string knobText(const gi::Knob& knob, double value) {
    if (knob.kind == gi::Knob::Kind::Bool)
        return value != 0.0 ? "on" : "off";
    if (knob.kind == gi::Knob::Kind::Enum)
        return knob.choices.at(size_t(value));
    char buf[64];
    if (knob.kind == gi::Knob::Kind::Float)
        std::snprintf(buf, sizeof(buf), "%.9g", value);
    else
        std::snprintf(buf, sizeof(buf), "%llu", static_cast<unsigned long long>(value));
    return buf;
}

} // namespace

Result<std::unique_ptr<Ui>> Ui::create(Context& ctx, const Window& window, uint32_t framesInFlight) {
    std::unique_ptr<Ui> ui(new Ui(ctx));
    VkDescriptorPoolSize sizes{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 8};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    poolInfo.maxSets = 8;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &sizes;
    VKGI_CHECK(vkCreateDescriptorPool(ctx.device(), &poolInfo, nullptr, &ui->m_pool));

    // Loads what the tone-map pass wrote and keeps the layout the graph put the image in; the
    // graph's barriers order it against that pass and against presentation.
    VkAttachmentDescription color{};
    color.format = Swapchain::kFormat;
    color.samples = VK_SAMPLE_COUNT_1_BIT;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    color.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &ref;
    VkRenderPassCreateInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rp.attachmentCount = 1;
    rp.pAttachments = &color;
    rp.subpassCount = 1;
    rp.pSubpasses = &subpass;
    VKGI_CHECK(vkCreateRenderPass(ctx.device(), &rp, nullptr, &ui->m_renderPass));

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini next to the user's files
    ImGui::StyleColorsDark();
    if (!ImGui_ImplGlfw_InitForVulkan(window.handle(), true))
        return makeError("ImGui GLFW backend initialisation failed");
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = ctx.instance();
    info.PhysicalDevice = ctx.physicalDevice();
    info.Device = ctx.device();
    info.QueueFamily = ctx.queueFamily();
    info.Queue = ctx.queue();
    info.DescriptorPool = ui->m_pool;
    info.MinImageCount = std::max(framesInFlight, 2u);
    info.ImageCount = std::max(framesInFlight, 2u);
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = checkVk;
    if (!ImGui_ImplVulkan_Init(&info, ui->m_renderPass)) {
        ImGui_ImplGlfw_Shutdown();
        return makeError("ImGui Vulkan backend initialisation failed");
    }
    ui->m_backendsReady = true;
    ctx.submitAndWait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
    return ui;
}

Ui::~Ui() {
    vkDeviceWaitIdle(m_ctx.device());
    if (m_backendsReady) {
        ImGui_ImplVulkan_Shutdown();
        ImGui_ImplGlfw_Shutdown();
    }
    if (ImGui::GetCurrentContext())
        ImGui::DestroyContext();
    destroyFramebuffers();
    if (m_renderPass)
        vkDestroyRenderPass(m_ctx.device(), m_renderPass, nullptr);
    if (m_pool)
        vkDestroyDescriptorPool(m_ctx.device(), m_pool, nullptr);
}

void Ui::destroyFramebuffers() {
    for (VkFramebuffer f : m_framebuffers)
        vkDestroyFramebuffer(m_ctx.device(), f, nullptr);
    m_framebuffers.clear();
}

void Ui::setTargets(const Swapchain& swapchain) {
    destroyFramebuffers();
    m_extent = swapchain.extent();
    for (uint32_t i = 0; i < swapchain.imageCount(); ++i) {
        VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        info.renderPass = m_renderPass;
        info.attachmentCount = 1;
        info.pAttachments = &swapchain.image(i).view;
        info.width = m_extent.width;
        info.height = m_extent.height;
        info.layers = 1;
        VkFramebuffer f = VK_NULL_HANDLE;
        VKGI_CHECK(vkCreateFramebuffer(m_ctx.device(), &info, nullptr, &f));
        m_framebuffers.push_back(f);
    }
}

bool Ui::wantsMouse() const {
    return m_visible && ImGui::GetIO().WantCaptureMouse;
}

bool Ui::wantsKeyboard() const {
    return m_visible && ImGui::GetIO().WantCaptureKeyboard;
}

bool Ui::knobControls(gi::GiSettings& edited) {
    bool changed = false;
    for (const gi::Knob& knob : gi::knobs()) {
        if (knob.technique && *knob.technique != edited.technique)
            continue;
        double value = knobValue(knob, edited);
        bool commit = false;
        ImGui::PushID(knob.name.c_str());
        if (knob.kind == gi::Knob::Kind::Bool) {
            bool on = value != 0.0;
            commit = ImGui::Checkbox(knob.name.c_str(), &on);
            value = on ? 1.0 : 0.0;
        } else if (knob.kind == gi::Knob::Kind::Enum) {
            int current = int(value);
            std::vector<const char*> names;
            for (const std::string& c : knob.choices)
                names.push_back(c.c_str());
            commit = ImGui::Combo(knob.name.c_str(), &current, names.data(), int(names.size()));
            value = current;
        } else if (knob.kind == gi::Knob::Kind::Uint) {
            uint32_t v = uint32_t(value), lo = uint32_t(knob.min), hi = uint32_t(knob.max);
            ImGui::DragScalar(knob.name.c_str(), ImGuiDataType_U32, &v, 0.2f, &lo, &hi, nullptr,
                              ImGuiSliderFlags_AlwaysClamp);
            commit = ImGui::IsItemDeactivatedAfterEdit(); // rebuild once, not per drag step
            value = v;
        } else {
            float v = float(value);
            float speed = float(knob.max - knob.min) / 1000.0f;
            ImGui::DragFloat(knob.name.c_str(), &v, speed, float(knob.min), float(knob.max), "%.4g",
                             ImGuiSliderFlags_AlwaysClamp);
            commit = ImGui::IsItemDeactivatedAfterEdit();
            value = v;
        }
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("%s", knob.help.c_str());
        ImGui::PopID();
        if (commit) {
            auto ok = gi::setKnob(edited, knob.name, knobText(knob, value));
            m_knobError = ok ? std::string() : ok.error().message;
            changed = changed || ok.ok();
        }
    }
    if (!m_knobError.empty())
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "%s", m_knobError.c_str());
    return changed;
}

bool Ui::sceneControls(PanelModel& model) {
    Scene& scene = *model.scene;
    Aabb bounds = scene.bounds();
    float speed = bounds.valid() ? glm::length(bounds.extent()) * 0.002f : 0.01f;
    bool edited = false;
    if (!scene.lights.empty()) {
        m_selectedLight = std::min(m_selectedLight, int(scene.lights.size()) - 1);
        Light& light = scene.lights[size_t(m_selectedLight)];
        if (ImGui::BeginCombo("light", light.name.empty() ? "(unnamed)" : light.name.c_str())) {
            for (int i = 0; i < int(scene.lights.size()); ++i) {
                ImGui::PushID(i);
                const std::string& name = scene.lights[size_t(i)].name;
                if (ImGui::Selectable(name.empty() ? "(unnamed)" : name.c_str(), i == m_selectedLight))
                    m_selectedLight = i;
                ImGui::PopID();
            }
            ImGui::EndCombo();
        }
        if (light.type != LightType::Directional)
            edited |= ImGui::DragFloat3("light position", &light.position.x, speed);
        edited |= ImGui::DragFloat("light intensity", &light.intensity, light.intensity * 0.01f + 1e-4f, 0.0f, 1e9f,
                                   "%.4g", ImGuiSliderFlags_AlwaysClamp);
    }
    if (model.dynamicObject) {
        Instance& object = scene.instances[*model.dynamicObject];
        const std::string& name = scene.meshes[object.mesh].name;
        ImGui::Text("object: %s", name.c_str());
        edited |= ImGui::DragFloat3("object position", &object.transform[3].x, speed);
    }
    ImGui::Checkbox("animate light + object", model.animate);
    return edited;
}

PanelActions Ui::build(PanelModel& model) {
    PanelActions actions;
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    if (m_visible) {
        ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
        ImGui::Begin("vkgi-view (H hides)");
        ImGui::PushItemWidth(-ImGui::GetFontSize() * 8.0f); // room for the labels
        ImGui::Text("%ux%u  frame %.1f ms  GPU %.1f ms", model.size.width, model.size.height, model.frameMs,
                    model.gpuMs);
        gi::GiSettings edited = *model.settings;
        int current = int(edited.technique);
        std::vector<std::string> names = gi::techniqueNames();
        if (ImGui::BeginCombo("technique", gi::toString(edited.technique))) {
            for (const std::string& name : names) {
                auto t = gi::parseTechnique(name);
                if (t && ImGui::Selectable(name.c_str(), int(*t) == current) && int(*t) != current) {
                    edited.technique = *t;
                    actions.settings = edited;
                }
            }
            ImGui::EndCombo();
        }
        if (ImGui::CollapsingHeader("settings (knob table)") && knobControls(edited))
            actions.settings = edited;
        if (ImGui::CollapsingHeader("scene"))
            actions.sceneEdited = sceneControls(model);
        ImGui::DragFloat("exposure", model.exposure, 0.01f, 1e-6f, 1e6f, "%.4g",
                         ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
        ImGui::Text("camera: %s (Tab)", model.flyCamera ? "fly" : "orbit");
        ImGui::SameLine();
        actions.toggleCamera = ImGui::SmallButton("switch");
        ImGui::SameLine();
        actions.resetCamera = ImGui::SmallButton("reset");
        actions.screenshot = ImGui::Button("screenshot (F12)");
        if (!model.status.empty())
            ImGui::TextWrapped("%s", model.status.c_str());
        if (ImGui::CollapsingHeader("GPU ms per pass", ImGuiTreeNodeFlags_DefaultOpen) && model.passes &&
            ImGui::BeginTable("passes", 2, ImGuiTableFlags_RowBg)) {
            for (const rg::PassTiming& p : *model.passes) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(p.name.c_str());
                ImGui::TableNextColumn();
                ImGui::Text("%8.3f", p.ms);
            }
            ImGui::EndTable();
        }
        ImGui::PopItemWidth();
        ImGui::End();
    }
    ImGui::Render();
    return actions;
}

rg::ImageHandle Ui::addPass(rg::RenderGraph& graph, rg::ImageHandle target, uint32_t imageIndex) {
    ImDrawData* draw = ImGui::GetDrawData();
    if (!m_visible || !draw || draw->CmdListsCount == 0)
        return target;
    VkFramebuffer framebuffer = m_framebuffers.at(imageIndex);
    VkRenderPass renderPass = m_renderPass;
    VkExtent2D extent = m_extent;
    graph.addPass(
        "view.ui", [&](rg::PassBuilder& b) { target = b.write(target, rg::Access::ColorAttachmentReadWrite); },
        [=](rg::PassContext& pc) {
            VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
            begin.renderPass = renderPass;
            begin.framebuffer = framebuffer;
            begin.renderArea.extent = extent;
            vkCmdBeginRenderPass(pc.cmd(), &begin, VK_SUBPASS_CONTENTS_INLINE);
            ImGui_ImplVulkan_RenderDrawData(draw, pc.cmd());
            vkCmdEndRenderPass(pc.cmd());
        });
    return target;
}

} // namespace vkgi::view
