// Embedded SPIR-V lookup (vkgi/pipeline.hpp, cmake/CompileShaders.cmake) without a device: the
// tables linked into this binary (the GI library's and the tests' own) answer by shader name, a
// table registers for exactly its lifetime, a later table shadows an earlier one, and an unknown
// name or a corrupt entry is an error naming the shader.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "vkgi/pipeline.hpp"

namespace vkgi {
namespace {

constexpr uint32_t kMagic = 0x07230203u;

TEST(EmbeddedSpirv, LinkedTablesHoldTheGiAndTestShaders) {
    for (const char* name : {"gi/lpv/inject.comp", "gi/direct/raster.vert", "engine/test/tiny.comp",
                             "gi/lpv/gather_baseline.comp"}) {
        auto code = loadSpirv(name);
        ASSERT_TRUE(code) << code.error().message;
        EXPECT_GT(code->size(), 5u) << name;
        EXPECT_EQ((*code)[0], kMagic) << name;
    }
}

TEST(EmbeddedSpirv, UnknownNameIsAnErrorNamingIt) {
    auto code = loadSpirv("gi/no_such_shader.comp");
    ASSERT_FALSE(code);
    EXPECT_NE(code.error().message.find("gi/no_such_shader.comp"), std::string::npos) << code.error().message;
}

TEST(EmbeddedSpirv, TableIsFoundWhileItLivesAndShadowsEarlierOnes) {
    static const uint32_t first[] = {kMagic, 0x00010600u, 0, 1, 0, 0};
    static const uint32_t second[] = {kMagic, 0x00010600u, 0, 2, 0, 0, 0};
    const EmbeddedSpirv firstEntry[] = {{"unit/fake.comp", first, 6}};
    const EmbeddedSpirv secondEntry[] = {{"unit/fake.comp", second, 7}};
    {
        SpirvTable outer(firstEntry);
        auto code = loadSpirv("unit/fake.comp");
        ASSERT_TRUE(code) << code.error().message;
        EXPECT_EQ(code->size(), 6u);
        {
            SpirvTable inner(secondEntry);
            code = loadSpirv("unit/fake.comp");
            ASSERT_TRUE(code) << code.error().message;
            EXPECT_EQ(code->size(), 7u);
        }
        code = loadSpirv("unit/fake.comp");
        ASSERT_TRUE(code) << code.error().message;
        EXPECT_EQ(code->size(), 6u);
    }
    EXPECT_FALSE(loadSpirv("unit/fake.comp"));
    EXPECT_TRUE(loadSpirv("gi/lpv/inject.comp")); // the static tables stay registered
}

TEST(EmbeddedSpirv, CorruptEntryIsAnErrorNamingIt) {
    static const uint32_t notSpirv[] = {0xdeadbeefu, 0, 0, 0, 0, 0};
    const EmbeddedSpirv entry[] = {{"unit/corrupt.comp", notSpirv, 6}};
    SpirvTable table(entry);
    auto code = loadSpirv("unit/corrupt.comp");
    ASSERT_FALSE(code);
    EXPECT_NE(code.error().message.find("unit/corrupt.comp"), std::string::npos) << code.error().message;
}

} // namespace
} // namespace vkgi
