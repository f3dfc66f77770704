// The build tree's SPIR-V folder, for binaries linked in the build tree (GI_SPIRV_DIR defined),
// or none for the installed package, which finds its SPIR-V at run time (engine spirvDir()).
namespace vkgi::detail {

const char* buildTreeSpirvDir() {
#ifdef GI_SPIRV_DIR
    return GI_SPIRV_DIR;
#else
    return nullptr;
#endif
}

} // namespace vkgi::detail
