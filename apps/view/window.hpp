#pragma once
// vkgi-view's GLFW window and its Vulkan swapchain. The window collects the input events the
// viewer consumes once per frame (key presses, scroll, resizes); the swapchain owns the
// surface images wrapped as vkgi::Image (so the render graph can import them) and one
// "render finished" semaphore per image, which present waits on.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "vkgi/context.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/result.hpp"

struct GLFWwindow;

namespace vkgi::view {

// What happened since the last takeEvents().
struct WindowEvents {
    std::vector<int> keysPressed; // GLFW key codes, in order
    double scrollY = 0.0;
    bool resized = false;
};

class Window {
public:
    // Initialises GLFW (fails without a display: run under xvfb-run on headless machines).
    static Result<std::unique_ptr<Window>> create(const std::string& title, uint32_t width, uint32_t height);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    // Instance extensions the surface needs (VK_KHR_surface + the platform one).
    static std::vector<const char*> requiredInstanceExtensions();
    Result<VkSurfaceKHR> createSurface(VkInstance instance) const;

    GLFWwindow* handle() const { return m_window; }
    bool shouldClose() const;
    void requestClose();
    void resize(uint32_t width, uint32_t height);
    // Framebuffer size in pixels (0 x 0 while minimised).
    void framebufferSize(uint32_t& width, uint32_t& height) const;
    WindowEvents takeEvents();

private:
    Window() = default;
    static void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
    static void onScroll(GLFWwindow* window, double x, double y);
    static void onResize(GLFWwindow* window, int width, int height);
    GLFWwindow* m_window = nullptr;
    WindowEvents m_events;
};

enum class PresentMode { Fifo, Mailbox, Immediate };

class Swapchain {
public:
    // Colour format of every swapchain: B8G8R8A8_UNORM is the one format lavapipe's X11 swapchain
    // offers with STORAGE usage (the tone-map pass writes it from a compute shader).
    static constexpr VkFormat kFormat = VK_FORMAT_B8G8R8A8_UNORM;
    static constexpr VkImageUsageFlags kUsage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;

    // Takes ownership of `surface`. Errors when the queue cannot present to it or the surface
    // lacks the format/usage above.
    static Result<std::unique_ptr<Swapchain>> create(Context& ctx, VkSurfaceKHR surface, PresentMode mode,
                                                     uint32_t width, uint32_t height);
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    // Rebuilds for a new framebuffer size; the device must be idle (no frame uses the images).
    Result<void> recreate(uint32_t width, uint32_t height);

    // Index of the next image, or kNoImage when the swapchain is out of date (recreate it).
    // `acquired` is signalled when the image may be written.
    uint32_t acquire(VkSemaphore acquired);
    // Queues image `index` for presentation after renderFinished(index). False: out of date or
    // suboptimal, recreate before the next frame.
    bool present(uint32_t index);

    uint32_t imageCount() const { return uint32_t(m_images.size()); }
    const Image& image(uint32_t index) const { return m_images[index]; }
    VkSemaphore renderFinished(uint32_t index) const { return m_renderFinished[index]; }
    VkExtent2D extent() const { return m_extent; }
    const char* presentModeName() const;
    static constexpr uint32_t kNoImage = ~0u;

private:
    explicit Swapchain(Context& ctx) : m_ctx(ctx) {}
    void destroyImages();
    Context& m_ctx;
    VkSurfaceKHR m_surface = VK_NULL_HANDLE;
    VkSwapchainKHR m_swapchain = VK_NULL_HANDLE;
    VkPresentModeKHR m_mode = VK_PRESENT_MODE_FIFO_KHR;
    VkExtent2D m_extent{};
    std::vector<Image> m_images;
    std::vector<VkSemaphore> m_renderFinished;
};

} // namespace vkgi::view
