#pragma once
// vkgi-view's command line (one-line errors, exit code 2) and help text.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vkgi/result.hpp"
#include "window.hpp"

#include "../common/scene_overrides.hpp"

namespace vkgi::view {

struct Options {
    std::string scene = "cornell"; // built-in name or .gltf/.glb, as vkgi-render --scene
    std::string technique = "none";
    uint32_t width = 640; // initial window size = render size
    uint32_t height = 480;
    std::vector<std::pair<std::string, std::string>> knobs; // --name value, from vkgi/knobs.hpp
    float exposure = 1.0f;                                  // display and screenshot PNG
    PresentMode present = PresentMode::Fifo;
    bool validation = false;
    bool ui = true;
    // Scripted mode: render `frames` frames with the camera of `cameraScript` at t = i/(frames-1);
    // the last frame is captured to `screenshot` (.exr, plus the .png beside it).
    std::optional<uint32_t> frames;
    std::string cameraScript = "still";
    bool animate = false; // move the light and the dynamic object along loops that end where they start
    std::optional<std::filesystem::path> screenshot;
    // Scripted window resize before frame `resizeFrame` (exercises swapchain recreation in CI).
    std::optional<uint32_t> resizeFrame;
    uint32_t resizeWidth = 0, resizeHeight = 0;
    // Scripted technique switch before frame `switchFrame` (rebuilds the GiSystem, as the panel does).
    std::optional<uint32_t> switchFrame;
    std::string switchTechnique;
    bool exitAfterFrames = false;
    bool help = false;
    std::optional<apps::CameraSpec> camera; // --camera: the start camera, replacing the scene's
    std::vector<Light> lights;              // --light: added to the scene's
};

Result<Options> parseArgs(int argc, const char* const* argv);
std::string helpText();

} // namespace vkgi::view
