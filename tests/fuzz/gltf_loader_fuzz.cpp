// libFuzzer target for the glTF loader: any byte string, as .gltf or .glb, must give a scene
// that passes validateScene or a one-line error naming the file — never a crash, a hang, an
// exception or a sanitizer report. Seed corpus: tests/assets/gltf/ (bad/ for the hand-made
// hostile files, fuzz/ for what earlier fuzz runs found, merged with -merge=1). The input is
// written to a file in a folder of this process's own, which is removed at exit.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "vkgi/gltf_loader.hpp"

namespace {

// One folder per process for the scratch file, removed when the process exits (libFuzzer
// returns from main or calls exit on every normal stop).
class ScratchFolder {
public:
    ScratchFolder()
        : m_path(std::filesystem::temp_directory_path() / ("vkgi-fuzz-" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(m_path);
    }
    ~ScratchFolder() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }
    std::filesystem::path file(const char* ext) const { return m_path / (std::string("input") + ext); }

private:
    std::filesystem::path m_path;
};

const ScratchFolder& scratch() {
    static const ScratchFolder folder;
    return folder;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    // The first byte picks the container, so the fuzzer explores both parsers.
    const char* ext = (size > 0 && (data[0] & 1)) ? ".glb" : ".gltf";
    std::filesystem::path file = scratch().file(ext);
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
    std::error_code ec;
    std::filesystem::remove(file, ec);
    return 0;
}
