// C++/GLSL bridge: lets one header declare a shader-visible struct or function for both
// languages. In C++ the GLSL vector types map to GLM inside namespace vkgi::gpu and structs
// get 16-byte alignment; GI_CHECK_SIZE/GI_CHECK_OFFSET pin the std140/std430 layout.
// Rule: shared structs use vec4/uvec4/ivec4/mat4 fields only (no vec3, no bare scalars).
#ifndef VKGI_SHARED_BRIDGE_H
#define VKGI_SHARED_BRIDGE_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#define GI_NAMESPACE_BEGIN                                                                                             \
    namespace vkgi::gpu {                                                                                              \
    using namespace glm;                                                                                               \
    using uint = std::uint32_t;
#define GI_NAMESPACE_END }
#define GI_GPU_STRUCT(name) struct alignas(16) name
#define GI_INLINE inline
#define GI_CHECK_SIZE(T, n) static_assert(sizeof(T) == (n), #T ": C++ size differs from the GLSL layout")
#define GI_CHECK_OFFSET(T, m, n) static_assert(offsetof(T, m) == (n), #T "::" #m ": C++ offset differs from GLSL")
#else
#define GI_NAMESPACE_BEGIN
#define GI_NAMESPACE_END
#define GI_GPU_STRUCT(name) struct name
#define GI_INLINE
#define GI_CHECK_SIZE(T, n)
#define GI_CHECK_OFFSET(T, m, n)
#endif

#endif
