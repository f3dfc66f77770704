# vkgi_warnings: INTERFACE target carrying the project's warning flags (errors with GI_WERROR).
add_library(vkgi_warnings INTERFACE)
target_compile_options(vkgi_warnings INTERFACE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align
    -Wunused -Woverloaded-virtual -Wnull-dereference -Wimplicit-fallthrough
    # Vulkan create-infos are value-initialised from their sType ({VK_STRUCTURE_TYPE_...}) on purpose.
    -Wno-missing-field-initializers>
    $<$<BOOL:${GI_WERROR}>:-Werror>)
