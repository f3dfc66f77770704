#pragma once
// glTF 2.0 (.gltf / .glb) to the CPU Scene, via Debian's tinygltf shared library.
//
// Loaded: the default scene's node hierarchy flattened to world transforms (matrix or TRS);
// triangle primitives, indexed or not, with POSITION/NORMAL/TEXCOORD_0 of any component type
// (normalized integers decoded); metallic-roughness materials (baseColor factor + texture as
// RGBA8, metallic/roughness factors, emissiveFactor x KHR_materials_emissive_strength,
// doubleSided); KHR_lights_punctual lights placed by their node (shining down the node's -Z);
// the first perspective camera met in the hierarchy (looking down its node's -Z, +Y up).
//
// Never throws and never crashes on bad input. Fatal problems give a one-line error naming the
// file ("scene.gltf: accessor 3 reads past the end of buffer view 1"). Repairs and ignored
// features become one-line warnings, also prefixed with the file:
//   - non-triangle primitives, skins, morph targets, animations, orthographic cameras, textures
//     other than baseColor, texCoord sets other than 0, unsupported extensions in extensionsUsed:
//     ignored, named in a warning (an unsupported extension in extensionsRequired is an error);
//   - triangles with a non-finite vertex position, or a zero area (|cross| <= 1e-7 x longest
//     edge^2, i.e. below float precision) are dropped; unreferenced vertices are compacted away;
//   - non-finite or zero-length normals are replaced by the area-weighted normal of the
//     triangles around the vertex (the face normal for an unshared vertex); missing normals are
//     computed the same way; non-finite texture coordinates become 0;
//   - an undecodable or missing image leaves the material untextured;
//   - a light with a non-finite or negative intensity is skipped; spot cones are clamped to
//     0 <= inner <= outer <= pi/2;
//   - a node whose world transform is singular (a zero scale, an all-zero matrix, axes collapsed
//     onto a plane or line) or places it beyond kMaxCoordinate: its mesh is not drawn (warning);
//   - a KHR_lights_punctual light index that is not an index of the file's lights: ignored;
//   - URIs outside the scene's folder and files over the size limit: see GltfLoadOptions;
//   - no punctual lights is a warning (emission may still light the scene); no triangle at all
//     after repairs is an error.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/result.hpp"
#include "vkgi/scene.hpp"

namespace vkgi {

struct GltfLoadOptions {
    // Buffer and image URIs resolve inside the scene file's folder and its subfolders (after
    // "..", symbolic links and absolute paths are resolved); a URI outside it is not read: an
    // image is dropped with a warning, a buffer is an error. True lifts the restriction.
    bool allowOutsideFolder = false;
    // Largest file the loader reads (the scene file, each buffer and image), checked before
    // reading; a GLB's stated length must also match its file size.
    uint64_t maxFileBytes = uint64_t(1) << 30;
};

// Loads a .gltf or .glb file (format detected from the content). Appends warnings if given.
Result<Scene> loadGltf(const std::filesystem::path& file, std::vector<std::string>* warnings = nullptr,
                       const GltfLoadOptions& options = {});

// A built-in scene name (see builtinSceneNames()) or a path to a glTF file.
Result<Scene> loadScene(std::string_view nameOrPath, const BuiltinSceneParams& p = {},
                        std::vector<std::string>* warnings = nullptr, const GltfLoadOptions& options = {});

} // namespace vkgi
