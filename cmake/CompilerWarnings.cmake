# vkgi_warnings: INTERFACE target carrying the project's warning flags (errors with GI_WERROR).
add_library(vkgi_warnings INTERFACE)
target_compile_options(vkgi_warnings INTERFACE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align
    -Wunused -Woverloaded-virtual -Wnull-dereference -Wimplicit-fallthrough
    # Vulkan create-infos are value-initialised from their sType ({VK_STRUCTURE_TYPE_...}) on purpose.
    -Wno-missing-field-initializers>
    # GCC 12 at -O3 (Release) reports -Wrestrict inside std::string's operator+ on "literal" +
    # std::string (GCC bug 105329, fixed in 13): off for GCC 12 and older, so Release builds
    # with GI_WERROR.
    $<$<AND:$<COMPILE_LANGUAGE:CXX>,$<CXX_COMPILER_ID:GNU>,$<VERSION_LESS:$<CXX_COMPILER_VERSION>,13>>:-Wno-restrict>
    $<$<BOOL:${GI_WERROR}>:-Werror>)
