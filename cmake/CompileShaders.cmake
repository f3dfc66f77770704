# gi_add_spirv(<target> ROOT <dir> SOURCES <files...> INCLUDES <dirs...>)
# One glslangValidator command per shader; --depfile makes a header edit rebuild exactly the
# shaders that include it. Output: ${CMAKE_BINARY_DIR}/spirv/<path relative to ROOT>.spv.
set(GI_SPIRV_DIR "${CMAKE_BINARY_DIR}/spirv")
function(gi_add_spirv target)
    cmake_parse_arguments(ARG "" "ROOT" "SOURCES;INCLUDES" ${ARGN})
    set(include_flags)
    foreach(dir IN LISTS ARG_INCLUDES)
        list(APPEND include_flags "-I${dir}")
    endforeach()
    set(debug_flags)
    if(GI_SHADER_DEBUG)
        set(debug_flags -g)
    endif()
    set(outputs)
    foreach(src IN LISTS ARG_SOURCES)
        get_filename_component(abs "${src}" ABSOLUTE)
        file(RELATIVE_PATH rel "${ARG_ROOT}" "${abs}")
        set(out "${GI_SPIRV_DIR}/${rel}.spv")
        get_filename_component(out_dir "${out}" DIRECTORY)
        add_custom_command(
            OUTPUT "${out}"
            COMMAND ${CMAKE_COMMAND} -E make_directory "${out_dir}"
            COMMAND Vulkan::glslangValidator -V --target-env vulkan1.3 ${include_flags} ${debug_flags}
                    --depfile "${out}.d" -o "${out}" "${abs}"
            DEPENDS "${abs}"
            DEPFILE "${out}.d"
            COMMENT "glslang ${rel}"
            VERBATIM)
        list(APPEND outputs "${out}")
    endforeach()
    add_custom_target(${target} ALL DEPENDS ${outputs})
endfunction()
