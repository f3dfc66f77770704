// The GPU scene enters each frame's graph as external, read-only resources. uploadScene and
// updateSceneTransforms end with a full memory barrier in their own submission, so the state
// a frame finds them in is "read", and no pass of the graph writes them.
#include "direct/direct_passes.hpp"

namespace vkgi::gi {

SceneHandles importScene(rg::RenderGraph& graph, const GpuScene& scene) {
    using rg::Access;
    SceneHandles h;
    h.vertices = graph.importBuffer("scene.vertices", scene.vertices, Access::VertexShaderStorageRead);
    h.indices = graph.importBuffer("scene.indices", scene.indices, Access::IndexBufferRead);
    h.instances = graph.importBuffer("scene.instances", scene.instances, Access::VertexShaderStorageRead);
    h.materials = graph.importBuffer("scene.materials", scene.materials, Access::FragmentStorageRead);
    h.lights = graph.importBuffer("scene.lights", scene.lights, Access::ComputeStorageRead);
    h.textures = graph.importImage("scene.textures", scene.textures, Access::FragmentSampledRead);
    return h;
}

} // namespace vkgi::gi
