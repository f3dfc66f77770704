# `cmake --install` layout (relocatable: nothing below holds a build or install path):
#   lib/libvkgi_{engine,gi}.a       the core: vkgi::engine, vkgi::gi (shaders embedded)
#   lib/libvkgi_{io,stb}.a          component io: vkgi::io (glTF, EXR/PNG, image metrics)
#   lib/libvkgi_reference.a         component reference: vkgi::reference (Embree path tracer)
#   lib/libvkgi_bench.a             component bench: vkgi::bench (bench tables, JSON, plots)
#   include/vkgi/..., include/vkgi/rg/...          the public headers of each part
#   lib/cmake/vkgi/vkgiConfig.cmake, vkgiConfigVersion.cmake, vkgi{,-io,-reference,-bench}Targets*.cmake
# Each component has its own export set, so the core's targets file names no other package and
# vkgiConfig.cmake looks for a component's dependencies only when it is requested.
include(CMakePackageConfigHelpers)

set(VKGI_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/vkgi")

function(vkgi_install_part export_name)
    cmake_parse_arguments(ARG "" "" "TARGETS" ${ARGN})
    install(TARGETS ${ARG_TARGETS}
        EXPORT ${export_name}
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}")
    install(EXPORT ${export_name} NAMESPACE vkgi:: DESTINATION "${VKGI_INSTALL_CMAKEDIR}")
endfunction()
vkgi_install_part(vkgiTargets TARGETS vkgi_engine vkgi_gi)
vkgi_install_part(vkgi-ioTargets TARGETS vkgi_io vkgi_stb)
vkgi_install_part(vkgi-referenceTargets TARGETS vkgi_reference)
vkgi_install_part(vkgi-benchTargets TARGETS vkgi_bench)

# The public API: gi.hpp and frame_data.hpp (host passes) with everything they include, plus the
# scene helpers a host uses to build scenes; then each component's own headers. The core's
# headers include none of the components'. Checked by tests/package, which compiles against the
# installed tree only.
set(VKGI_PUBLIC_ENGINE_HEADERS
    builtin_scenes.hpp camera.hpp context.hpp hdr_image.hpp pipeline.hpp resources.hpp result.hpp scene.hpp)
set(VKGI_PUBLIC_RG_HEADERS access.hpp blackboard.hpp render_graph.hpp transient_pool.hpp)
set(VKGI_PUBLIC_GI_HEADERS frame_data.hpp gi.hpp lpv.hpp vct.hpp version.hpp vpl.hpp)
set(VKGI_PUBLIC_IO_HEADERS gltf_loader.hpp image_io.hpp image_metrics.hpp)
set(VKGI_PUBLIC_REFERENCE_HEADERS reference.hpp)
set(VKGI_PUBLIC_BENCH_HEADERS bench.hpp)
list(TRANSFORM VKGI_PUBLIC_ENGINE_HEADERS PREPEND "${PROJECT_SOURCE_DIR}/engine/include/vkgi/")
list(TRANSFORM VKGI_PUBLIC_RG_HEADERS PREPEND "${PROJECT_SOURCE_DIR}/engine/include/vkgi/rg/")
list(TRANSFORM VKGI_PUBLIC_GI_HEADERS PREPEND "${PROJECT_SOURCE_DIR}/gi/include/vkgi/")
list(TRANSFORM VKGI_PUBLIC_IO_HEADERS PREPEND "${PROJECT_SOURCE_DIR}/engine/include/vkgi/")
list(TRANSFORM VKGI_PUBLIC_REFERENCE_HEADERS PREPEND "${PROJECT_SOURCE_DIR}/gi/include/vkgi/")
list(TRANSFORM VKGI_PUBLIC_BENCH_HEADERS PREPEND "${PROJECT_SOURCE_DIR}/gi/include/vkgi/")
install(FILES ${VKGI_PUBLIC_ENGINE_HEADERS} ${VKGI_PUBLIC_GI_HEADERS} ${VKGI_PUBLIC_IO_HEADERS}
    ${VKGI_PUBLIC_REFERENCE_HEADERS} ${VKGI_PUBLIC_BENCH_HEADERS}
    DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/vkgi")
install(FILES ${VKGI_PUBLIC_RG_HEADERS} DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/vkgi/rg")

configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/vkgiConfig.cmake.in"
    "${PROJECT_BINARY_DIR}/vkgiConfig.cmake"
    INSTALL_DESTINATION "${VKGI_INSTALL_CMAKEDIR}")
write_basic_package_version_file("${PROJECT_BINARY_DIR}/vkgiConfigVersion.cmake"
    VERSION "${PROJECT_VERSION}" COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/vkgiConfig.cmake" "${PROJECT_BINARY_DIR}/vkgiConfigVersion.cmake"
    DESTINATION "${VKGI_INSTALL_CMAKEDIR}")
