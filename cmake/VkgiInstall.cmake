# `cmake --install` layout (relocatable: nothing below holds a build or install path):
#   lib/libvkgi_{gi,engine,stb,spirv_location}.a   static libraries, exported as vkgi::gi, vkgi::engine
#   include/vkgi/..., include/vkgi/rg/...          the public headers (only those the API needs)
#   share/vkgi/spirv/**.spv                        SPIR-V the library loads at run time
#   lib/cmake/vkgi/vkgiConfig.cmake, vkgiConfigVersion.cmake, vkgiTargets*.cmake
# docs/embedding.md describes how a consumer finds the SPIR-V.
include(CMakePackageConfigHelpers)

set(VKGI_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/vkgi")

install(TARGETS vkgi_gi vkgi_engine vkgi_stb vkgi_spirv_installed
    EXPORT vkgiTargets
    ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
    LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}")
install(EXPORT vkgiTargets NAMESPACE vkgi:: DESTINATION "${VKGI_INSTALL_CMAKEDIR}")

# The public API: gi.hpp and frame_data.hpp (host passes) with everything they include, plus the
# scene/image helpers a host uses to build scenes and write images. Checked by tests/package,
# which compiles against the installed tree only.
set(VKGI_PUBLIC_ENGINE_HEADERS
    builtin_scenes.hpp camera.hpp context.hpp gltf_loader.hpp hdr_image.hpp image_io.hpp pipeline.hpp
    resources.hpp result.hpp scene.hpp)
set(VKGI_PUBLIC_RG_HEADERS access.hpp blackboard.hpp render_graph.hpp transient_pool.hpp)
set(VKGI_PUBLIC_GI_HEADERS frame_data.hpp gi.hpp lpv.hpp vct.hpp version.hpp vpl.hpp)
list(TRANSFORM VKGI_PUBLIC_ENGINE_HEADERS PREPEND "${PROJECT_SOURCE_DIR}/engine/include/vkgi/")
list(TRANSFORM VKGI_PUBLIC_RG_HEADERS PREPEND "${PROJECT_SOURCE_DIR}/engine/include/vkgi/rg/")
list(TRANSFORM VKGI_PUBLIC_GI_HEADERS PREPEND "${PROJECT_SOURCE_DIR}/gi/include/vkgi/")
install(FILES ${VKGI_PUBLIC_ENGINE_HEADERS} DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/vkgi")
install(FILES ${VKGI_PUBLIC_RG_HEADERS} DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/vkgi/rg")
install(FILES ${VKGI_PUBLIC_GI_HEADERS} DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/vkgi")

install(DIRECTORY "${GI_SPIRV_DIR}/" DESTINATION "${CMAKE_INSTALL_DATADIR}/vkgi/spirv"
    FILES_MATCHING PATTERN "*.spv")

configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/vkgiConfig.cmake.in"
    "${PROJECT_BINARY_DIR}/vkgiConfig.cmake"
    INSTALL_DESTINATION "${VKGI_INSTALL_CMAKEDIR}"
    PATH_VARS CMAKE_INSTALL_DATADIR)
write_basic_package_version_file("${PROJECT_BINARY_DIR}/vkgiConfigVersion.cmake"
    VERSION "${PROJECT_VERSION}" COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/vkgiConfig.cmake" "${PROJECT_BINARY_DIR}/vkgiConfigVersion.cmake"
    DESTINATION "${VKGI_INSTALL_CMAKEDIR}")
