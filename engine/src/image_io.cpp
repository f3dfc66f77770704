#include "vkgi/image_io.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <system_error>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <stb_image_write.h>

#include "vkgi/file_util.hpp"

namespace vkgi {

namespace {

namespace fs = std::filesystem;

// Largest image either format accepts: guards against garbage headers asking for huge buffers.
constexpr uint64_t kMaxPixels = uint64_t(1) << 28;

// Exception texts from OpenEXR may span lines; errors here are one line.
std::string oneLine(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    std::replace(s.begin(), s.end(), '\r', ' ');
    return s;
}

Error fileError(const fs::path& path, const std::string& what) {
    return makeError(path.string() + ": " + oneLine(what));
}

Result<void> checkWritable(const fs::path& path, const HdrImage& image) {
    if (image.empty() || image.width == 0 || image.height == 0)
        return fileError(path, "cannot write an empty image");
    if (uint64_t(image.width) * image.height > kMaxPixels)
        return fileError(path, "image too large to write");
    if (image.pixels.size() != size_t(image.width) * image.height)
        return fileError(path, "image pixel count does not match its width x height");
    if (path.filename().empty())
        return fileError(path, "not a file name");
    return {};
}

float srgbOetf(float v) {
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float acesFit(float v) {
    // Narkowicz 2015 fit of the ACES RRT+ODT; constants belong to the published fit.
    return (v * (2.51f * v + 0.03f)) / (v * (2.43f * v + 0.59f) + 0.14f);
}

} // namespace

glm::u8vec3 toneMapPixel(const glm::vec3& linear, const ToneMap& toneMap) {
    if (!std::isfinite(linear.x) || !std::isfinite(linear.y) || !std::isfinite(linear.z))
        return {255, 0, 255};
    glm::u8vec3 out;
    for (int c = 0; c < 3; ++c) {
        // Both curves are saturated long before 1e6; the cap keeps v*v in the ACES fit from
        // overflowing to inf/inf = NaN and maps an overflowing exposure product to white.
        float v = linear[c] * toneMap.exposure;
        v = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1e6f); // NaN only from a NaN/0*inf exposure
        float f = toneMap.curve == ToneMap::Curve::Aces ? acesFit(v) : v;
        f = std::clamp(f, 0.0f, 1.0f);
        out[c] = uint8_t(std::lround(srgbOetf(f) * 255.0f));
    }
    return out;
}

Result<void> writeExr(const fs::path& path, const HdrImage& image) {
    if (auto ok = checkWritable(path, image); !ok)
        return ok;
    Result<AtomicFile> file = AtomicFile::begin(path);
    if (!file)
        return file.error();
    try {
        Imf::Header header(int(image.width), int(image.height));
        header.compression() = Imf::ZIP_COMPRESSION;
        for (const char* name : {"R", "G", "B"})
            header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        Imf::FrameBuffer fb;
        // OpenEXR's slice API takes mutable pointers even for writing; the data is only read.
        char* base = reinterpret_cast<char*>(const_cast<glm::vec3*>(image.pixels.data()));
        const size_t xs = sizeof(glm::vec3), ys = xs * image.width;
        fb.insert("R", Imf::Slice(Imf::FLOAT, base + 0 * sizeof(float), xs, ys));
        fb.insert("G", Imf::Slice(Imf::FLOAT, base + 1 * sizeof(float), xs, ys));
        fb.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));
        {
            Imf::OutputFile out(file->temporary().c_str(), header); // closed (and flushed) at scope end
            out.setFrameBuffer(fb);
            out.writePixels(int(image.height));
        }
    } catch (const std::exception& e) {
        return fileError(path, std::string("cannot write EXR: ") + e.what());
    }
    return file->commit();
}

Result<HdrImage> readExr(const fs::path& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
        return fileError(path, "cannot read EXR: no such file");
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i dw = file.header().dataWindow();
        const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
        if (w <= 0 || h <= 0 || uint64_t(w) * uint64_t(h) > kMaxPixels)
            return fileError(path, "EXR data window has an unsupported size");
        for (const char* name : {"R", "G", "B"})
            if (!file.header().channels().findChannel(name))
                return fileError(path, std::string("EXR has no '") + name + "' channel");
        HdrImage image{uint32_t(w), uint32_t(h)};
        char* base = reinterpret_cast<char*>(image.pixels.data());
        const size_t xs = sizeof(glm::vec3), ys = xs * size_t(w);
        Imf::FrameBuffer fb;
        fb.insert("R", Imf::Slice::Make(Imf::FLOAT, base + 0 * sizeof(float), dw, xs, ys));
        fb.insert("G", Imf::Slice::Make(Imf::FLOAT, base + 1 * sizeof(float), dw, xs, ys));
        fb.insert("B", Imf::Slice::Make(Imf::FLOAT, base + 2 * sizeof(float), dw, xs, ys));
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        return image;
    } catch (const std::exception& e) {
        return fileError(path, std::string("cannot read EXR: ") + e.what());
    }
}

float autoExposure(const HdrImage& image) {
    double logSum = 0.0;
    uint64_t lit = 0;
    for (const glm::vec3& p : image.pixels) {
        const double l = 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
        if (!std::isfinite(l) || !(l > 1e-6))
            continue;
        logSum += std::log(l);
        ++lit;
    }
    if (lit == 0)
        return 1.0f;
    const double exposure = 0.18 / std::exp(logSum / double(lit));
    return float(std::clamp(exposure, 1e-9, 1e9));
}

Result<void> writePng(const fs::path& path, const HdrImage& image, const ToneMap& toneMap, uint64_t* nonFinite) {
    if (auto ok = checkWritable(path, image); !ok)
        return ok;
    std::vector<uint8_t> rgb(image.pixels.size() * 3);
    uint64_t bad = 0;
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        const glm::vec3& p = image.pixels[i];
        bad += (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) ? 0 : 1;
        glm::u8vec3 v = toneMapPixel(p, toneMap);
        rgb[3 * i + 0] = v.x;
        rgb[3 * i + 1] = v.y;
        rgb[3 * i + 2] = v.z;
    }
    if (nonFinite)
        *nonFinite = bad;
    std::vector<uint8_t> encoded;
    auto append = [](void* ctx, void* data, int size) {
        auto* out = static_cast<std::vector<uint8_t>*>(ctx);
        const auto* bytes = static_cast<const uint8_t*>(data);
        out->insert(out->end(), bytes, bytes + size);
    };
    if (!stbi_write_png_to_func(append, &encoded, int(image.width), int(image.height), 3, rgb.data(),
                                int(image.width) * 3))
        return fileError(path, "PNG encoding failed");
    return writeFileAtomic(path, std::span<const uint8_t>(encoded));
}

} // namespace vkgi
