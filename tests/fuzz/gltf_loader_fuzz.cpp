// libFuzzer target for the glTF loader: any byte string, as .gltf or .glb, must give a scene
// that passes validateScene or a one-line error naming the file — never a crash, a hang, an
// exception or a sanitizer report. Seed corpus: tests/assets/gltf/.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "engine/gltf_loader.hpp"

namespace {
std::filesystem::path scratch(const char* ext) {
    return std::filesystem::temp_directory_path() / ("vkgi-fuzz-" + std::to_string(::getpid()) + ext);
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    // The first byte picks the container, so the fuzzer explores both parsers.
    const char* ext = (size > 0 && (data[0] & 1)) ? ".glb" : ".gltf";
    std::filesystem::path file = scratch(ext);
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    }
    std::vector<std::string> warnings;
    auto scene = vkgi::loadGltf(file, &warnings);
    if (scene) {
        if (!vkgi::validateScene(*scene)) {
            std::fprintf(stderr, "loader returned a scene that fails validateScene\n");
            std::abort();
        }
    } else {
        const std::string& msg = scene.error().message;
        if (msg.empty() || msg.find('\n') != std::string::npos || msg.find(file.filename().string()) == std::string::npos) {
            std::fprintf(stderr, "error message is not one line naming the file: '%s'\n", msg.c_str());
            std::abort();
        }
    }
    return 0;
}
