// Output writing under hostile paths: symbolic links, names at the 255-byte limit, temporaries
// of killed processes, and folder chains of a failed write.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "vkgi/file_util.hpp"
#include "vkgi/image_io.hpp"
#include "support/test_env.hpp"

namespace vkgi {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) { return test::freshOutputDir(fs::path("file_util") / name); }

std::string readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

TEST(FileUtil, WritesThroughASymbolicLinkAsCpDoes) {
    const fs::path dir = freshDir("symlink");
    fs::create_directories(dir / "real");
    ASSERT_TRUE(writeFileAtomic(dir / "real" / "target.txt", "old"));
    fs::create_symlink(fs::path("real") / "target.txt", dir / "link.txt");
    ASSERT_TRUE(writeFileAtomic(dir / "link.txt", "new"));
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "link.txt"))) << "the link is kept";
    EXPECT_EQ(readAll(dir / "real" / "target.txt"), "new");
    // A dangling link creates its target.
    fs::create_symlink(fs::path("real") / "later.txt", dir / "dangling.txt");
    ASSERT_TRUE(writeFileAtomic(dir / "dangling.txt", "made"));
    EXPECT_EQ(readAll(dir / "real" / "later.txt"), "made");
    EXPECT_EQ(test::countEntries(dir / "real"), 2u) << "no temporary left beside the target";
    EXPECT_EQ(test::countEntries(dir), 3u);
}

// A valid name of 255 bytes (the usual NAME_MAX) must work: the temporary's name is short.
TEST(FileUtil, NamesUpToTheLimitWork) {
    const fs::path dir = freshDir("long");
    for (size_t len : {241u, 250u, 255u}) {
        const std::string name = std::string(len - 4, 'n') + ".exr";
        HdrImage img(2, 2);
        img.at(1, 1) = glm::vec3(1.0f);
        Result<void> ok = writeExr(dir / name, img);
        ASSERT_TRUE(ok) << len << ": " << ok.error().message;
        ASSERT_TRUE(writeFileAtomic(dir / (std::string(len - 4, 'j') + ".txt"), "x"));
    }
    EXPECT_EQ(test::countEntries(dir), 6u);
}

// A temporary of a process that no longer exists (killed during its write) is removed by the
// next write into the folder; one of a live process (this one) is left alone.
TEST(FileUtil, StaleTemporariesOfDeadProcessesAreRemoved) {
    const fs::path dir = freshDir("stale");
    const fs::path dead = dir / ".vkgi-2147483646-0.tmp"; // above any pid_max: never alive
    const fs::path live = dir / (".vkgi-1-0.tmp");           // init is always alive
    const fs::path other = dir / ".vkgi-notes.tmp";         // not ours: no pid
    for (const fs::path& p : {dead, live, other})
        std::ofstream(p) << "";
    ASSERT_TRUE(writeFileAtomic(dir / "out.txt", "x"));
    EXPECT_FALSE(fs::exists(dead));
    EXPECT_TRUE(fs::exists(live));
    EXPECT_TRUE(fs::exists(other));
}

TEST(FileUtil, FailedWriteLeavesNoFolderChain) {
    const fs::path dir = freshDir("folders");
    {
        // 45 nested folders of 100 bytes each: the path passes PATH_MAX (4096), so creation
        // fails part way; what was created is removed again.
        fs::path deep = dir;
        for (int i = 0; i < 45; ++i)
            deep /= std::string(100, char('a' + i % 26));
        Result<OutputFolders> folders = OutputFolders::create(deep / "out.exr");
        EXPECT_FALSE(folders);
        if (!folders) {
            EXPECT_NE(folders.error().message.find("cannot create folder"), std::string::npos);
        }
    }
    EXPECT_EQ(test::countEntries(dir), 0u);
    {
        Result<OutputFolders> folders = OutputFolders::create(dir / "x" / "y" / "out.txt");
        ASSERT_TRUE(folders) << folders.error().message;
        EXPECT_TRUE(fs::is_directory(dir / "x" / "y"));
        // Destroyed without release(): the write it was for did not happen.
    }
    EXPECT_FALSE(fs::exists(dir / "x"));
    {
        Result<OutputFolders> folders = OutputFolders::create(dir / "x" / "y" / "out.txt");
        ASSERT_TRUE(folders);
        ASSERT_TRUE(writeFileAtomic(dir / "x" / "y" / "out.txt", "kept"));
        folders->release();
    }
    EXPECT_EQ(readAll(dir / "x" / "y" / "out.txt"), "kept");
}

} // namespace
} // namespace vkgi
