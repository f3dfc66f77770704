# vkgi_warnings: INTERFACE target carrying the project's warning flags (errors with GI_WERROR).
add_library(vkgi_warnings INTERFACE)
target_compile_options(vkgi_warnings INTERFACE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align
    -Wunused -Woverloaded-virtual -Wnull-dereference -Wimplicit-fallthrough>
    $<$<BOOL:${GI_WERROR}>:-Werror>)
