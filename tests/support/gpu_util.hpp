#pragma once
// Recording helpers for GPU tests: layout set-up outside the render graph, and reading back a
// graph resource after running the graph.
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <vector>

#include "vkgi/context.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/rg/transient_pool.hpp"

namespace vkgi::test {

// Moves every mip of layer 0 of each image from UNDEFINED to GENERAL (contents discarded), with
// a full barrier: for tests that record dispatches by hand.
void toGeneral(VkCommandBuffer cmd, std::initializer_list<const Image*> images);

// Adds a pass copying mip 0 of every layer (or depth slice) of `image` into host memory, compiles
// and executes `graph` (with `pool`, or a pool of its own), and returns the texels, tightly packed
// layer after layer. `bytes` is their size; a different size of the image fails the test.
std::vector<uint8_t> runAndReadImage(Context& ctx, rg::RenderGraph& graph, rg::ImageHandle image, VkDeviceSize bytes,
                                     rg::TransientPool* pool = nullptr);
// The same for the first `bytes` of a buffer.
std::vector<uint8_t> runAndReadBuffer(Context& ctx, rg::RenderGraph& graph, rg::BufferHandle buffer, VkDeviceSize bytes,
                                      rg::TransientPool* pool = nullptr);

// Bytes reinterpreted as an array of T (trailing bytes that do not fill a T are dropped).
template <typename T> std::vector<T> asArray(const std::vector<uint8_t>& bytes) {
    std::vector<T> out(bytes.size() / sizeof(T));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
    return out;
}

} // namespace vkgi::test
