#include "window.hpp"

#include <algorithm>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "vk_check.hpp"

namespace vkgi::view {

namespace {

Window* owner(GLFWwindow* window) {
    return static_cast<Window*>(glfwGetWindowUserPointer(window));
}

VkPresentModeKHR toVk(PresentMode mode) {
    switch (mode) {
    case PresentMode::Mailbox:
        return VK_PRESENT_MODE_MAILBOX_KHR;
    case PresentMode::Immediate:
        return VK_PRESENT_MODE_IMMEDIATE_KHR;
    case PresentMode::Fifo:
        break;
    }
    return VK_PRESENT_MODE_FIFO_KHR;
}

} // namespace

Result<std::unique_ptr<Window>> Window::create(const std::string& title, uint32_t width, uint32_t height) {
    if (!glfwInit()) {
        const char* why = nullptr;
        glfwGetError(&why);
        return makeError(std::string("cannot open a window (glfwInit: ") + (why ? why : "unknown error") +
                         "); on a machine without a display run it under xvfb-run -a");
    }
    if (!glfwVulkanSupported()) {
        glfwTerminate();
        return makeError("GLFW found no Vulkan loader");
    }
    std::unique_ptr<Window> w(new Window());
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    w->m_window = glfwCreateWindow(int(width), int(height), title.c_str(), nullptr, nullptr);
    if (!w->m_window)
        return makeError("glfwCreateWindow failed for " + std::to_string(width) + "x" + std::to_string(height));
    glfwSetWindowUserPointer(w->m_window, w.get());
    // Installed before ImGui's, which chains to them.
    glfwSetKeyCallback(w->m_window, onKey);
    glfwSetScrollCallback(w->m_window, onScroll);
    glfwSetFramebufferSizeCallback(w->m_window, onResize);
    return w;
}

Window::~Window() {
    if (m_window)
        glfwDestroyWindow(m_window);
    glfwTerminate();
}

std::vector<const char*> Window::requiredInstanceExtensions() {
    uint32_t n = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&n);
    return std::vector<const char*>(names, names + n);
}

Result<VkSurfaceKHR> Window::createSurface(VkInstance instance) const {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    VkResult r = glfwCreateWindowSurface(instance, m_window, nullptr, &surface);
    if (r != VK_SUCCESS)
        return makeError(std::string("glfwCreateWindowSurface failed: ") + toString(r));
    return surface;
}

bool Window::shouldClose() const {
    return glfwWindowShouldClose(m_window);
}

void Window::requestClose() {
    glfwSetWindowShouldClose(m_window, GLFW_TRUE);
}

void Window::resize(uint32_t width, uint32_t height) {
    glfwSetWindowSize(m_window, int(width), int(height));
}

void Window::framebufferSize(uint32_t& width, uint32_t& height) const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(m_window, &w, &h);
    width = uint32_t(std::max(w, 0));
    height = uint32_t(std::max(h, 0));
}

WindowEvents Window::takeEvents() {
    return std::exchange(m_events, {});
}

void Window::onKey(GLFWwindow* window, int key, int, int action, int) {
    if (action == GLFW_PRESS)
        owner(window)->m_events.keysPressed.push_back(key);
}

void Window::onScroll(GLFWwindow* window, double, double y) {
    owner(window)->m_events.scrollY += y;
}

void Window::onResize(GLFWwindow* window, int, int) {
    owner(window)->m_events.resized = true;
}

Result<std::unique_ptr<Swapchain>> Swapchain::create(Context& ctx, VkSurfaceKHR surface, PresentMode mode,
                                                     uint32_t width, uint32_t height) {
    std::unique_ptr<Swapchain> s(new Swapchain(ctx));
    s->m_surface = surface;
    VkBool32 supported = VK_FALSE;
    VKGI_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physicalDevice(), ctx.queueFamily(), surface, &supported));
    if (!supported)
        return makeError("the device's graphics+compute queue cannot present to this window");
    uint32_t n = 0;
    VKGI_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physicalDevice(), surface, &n, nullptr));
    std::vector<VkSurfaceFormatKHR> formats(n);
    VKGI_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physicalDevice(), surface, &n, formats.data()));
    bool hasFormat = std::any_of(formats.begin(), formats.end(), [](const VkSurfaceFormatKHR& f) {
        return f.format == kFormat && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    });
    if (!hasFormat)
        return makeError("the window surface does not offer B8G8R8A8_UNORM / sRGB non-linear");
    VKGI_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(ctx.physicalDevice(), surface, &n, nullptr));
    std::vector<VkPresentModeKHR> modes(n);
    VKGI_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(ctx.physicalDevice(), surface, &n, modes.data()));
    s->m_mode = toVk(mode);
    if (std::find(modes.begin(), modes.end(), s->m_mode) == modes.end())
        return makeError(std::string("--present: the surface does not support ") + s->presentModeName());
    if (auto ok = s->recreate(width, height); !ok)
        return ok.error();
    return s;
}

Swapchain::~Swapchain() {
    vkDeviceWaitIdle(m_ctx.device());
    destroyImages();
    if (m_swapchain)
        vkDestroySwapchainKHR(m_ctx.device(), m_swapchain, nullptr);
    if (m_surface)
        vkDestroySurfaceKHR(m_ctx.instance(), m_surface, nullptr);
}

const char* Swapchain::presentModeName() const {
    switch (m_mode) {
    case VK_PRESENT_MODE_MAILBOX_KHR:
        return "mailbox";
    case VK_PRESENT_MODE_IMMEDIATE_KHR:
        return "immediate";
    default:
        return "fifo";
    }
}

void Swapchain::destroyImages() {
    for (Image& image : m_images)
        vkDestroyImageView(m_ctx.device(), image.view, nullptr);
    for (VkSemaphore s : m_renderFinished)
        vkDestroySemaphore(m_ctx.device(), s, nullptr);
    m_images.clear();
    m_renderFinished.clear();
}

Result<void> Swapchain::recreate(uint32_t width, uint32_t height) {
    VkSurfaceCapabilitiesKHR caps;
    VKGI_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(m_ctx.physicalDevice(), m_surface, &caps));
    if ((caps.supportedUsageFlags & kUsage) != kUsage)
        return makeError("the window surface does not allow STORAGE + COLOR_ATTACHMENT swapchain images");
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == 0xFFFFFFFFu) {
        extent.width = std::clamp(width, caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    uint32_t count = caps.minImageCount + 1;
    if (caps.maxImageCount != 0)
        count = std::min(count, caps.maxImageCount);

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = m_surface;
    info.minImageCount = count;
    info.imageFormat = kFormat;
    info.imageColorSpace = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = kUsage;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    info.presentMode = m_mode;
    info.clipped = VK_TRUE;
    info.oldSwapchain = m_swapchain;
    VkSwapchainKHR created = VK_NULL_HANDLE;
    VkResult r = vkCreateSwapchainKHR(m_ctx.device(), &info, nullptr, &created);
    if (r != VK_SUCCESS)
        return makeError(std::string("vkCreateSwapchainKHR failed: ") + toString(r));
    destroyImages();
    if (m_swapchain)
        vkDestroySwapchainKHR(m_ctx.device(), m_swapchain, nullptr);
    m_swapchain = created;
    m_extent = extent;

    uint32_t n = 0;
    VKGI_CHECK(vkGetSwapchainImagesKHR(m_ctx.device(), m_swapchain, &n, nullptr));
    std::vector<VkImage> images(n);
    VKGI_CHECK(vkGetSwapchainImagesKHR(m_ctx.device(), m_swapchain, &n, images.data()));
    for (uint32_t i = 0; i < n; ++i) {
        Image image;
        image.image = images[i];
        image.desc.format = kFormat;
        image.desc.width = extent.width;
        image.desc.height = extent.height;
        image.desc.usage = kUsage;
        VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        view.image = images[i];
        view.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view.format = kFormat;
        view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VKGI_CHECK(vkCreateImageView(m_ctx.device(), &view, nullptr, &image.view));
        image.mipViews = {image.view};
        std::string name = "view.swapchain." + std::to_string(i);
        m_ctx.setName(VK_OBJECT_TYPE_IMAGE, uint64_t(image.image), name.c_str());
        m_images.push_back(std::move(image));
        VkSemaphoreCreateInfo sem{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkSemaphore s = VK_NULL_HANDLE;
        VKGI_CHECK(vkCreateSemaphore(m_ctx.device(), &sem, nullptr, &s));
        m_renderFinished.push_back(s);
    }
    return {};
}

uint32_t Swapchain::acquire(VkSemaphore acquired) {
    uint32_t index = kNoImage;
    VkResult r = vkAcquireNextImageKHR(m_ctx.device(), m_swapchain, UINT64_MAX, acquired, VK_NULL_HANDLE, &index);
    if (r == VK_ERROR_OUT_OF_DATE_KHR)
        return kNoImage;
    if (r != VK_SUBOPTIMAL_KHR)
        VKGI_CHECK(r);
    return index; // suboptimal still signals `acquired`: render it, present() reports the recreate
}

bool Swapchain::present(uint32_t index) {
    VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    info.waitSemaphoreCount = 1;
    info.pWaitSemaphores = &m_renderFinished[index];
    info.swapchainCount = 1;
    info.pSwapchains = &m_swapchain;
    info.pImageIndices = &index;
    VkResult r = vkQueuePresentKHR(m_ctx.queue(), &info);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR)
        return false;
    VKGI_CHECK(r);
    return true;
}

} // namespace vkgi::view
