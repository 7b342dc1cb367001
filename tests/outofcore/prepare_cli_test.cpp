// `chcrt prepare` and `--scene file.chs` from the command line: success output, exit codes and one-line errors
// for bad input, no output file left behind on failure.
#include "tests/app/cli_fixture.h"
#include "tests/outofcore/outofcore_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

namespace chcrt {
namespace {

using CliRun = clitest::Result;

CliRun chcrt(const std::filesystem::path& dir, const std::string& arguments) { return clitest::runChcrt(dir, arguments); }

TEST(PrepareCli, PreparesAndInfoReadsTheFile) {
    test::ScratchDir dir;
    const CliRun prepare = chcrt(dir.file(""), "prepare --scene city:20k -o c.chs --subtree-triangles 2000 -q");
    ASSERT_EQ(prepare.exitCode, 0) << prepare.output;
    EXPECT_NE(prepare.output.find("20000 triangles"), std::string::npos) << prepare.output;
    const CliRun info = chcrt(dir.file(""), "info --scene c.chs");
    EXPECT_EQ(info.exitCode, 0) << info.output;
    EXPECT_NE(info.output.find("Prepared scene c.chs"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("city:20000:seed=1"), std::string::npos) << info.output;
}

TEST(PrepareCli, BadInputIsExit2WithOneLine) {
    test::ScratchDir dir;
    ASSERT_EQ(chcrt(dir.file(""), "prepare --scene city:20k -o c.chs -q").exitCode, 0);
    std::vector<char> bytes = test::readBytes(dir.file("c.chs"));
    bytes.resize(bytes.size() / 2);
    test::writeBytes(dir.file("half.chs"), bytes);
    for (const std::string& args : {std::string("render --scene half.chs -o x.png -q"),
                                    std::string("prepare --scene city:200k -o big.chs --memory-mb 1 -q"),
                                    std::string("prepare --scene city:20k -o c.txt -q"),
                                    std::string("prepare --scene city:20k -o g.chs --grid 0x3 -q"),
                                    std::string("render --scene missing.chs -o x.png -q")}) {
        const CliRun run = chcrt(dir.file(""), args);
        EXPECT_EQ(run.exitCode, 2) << args << ": " << run.output;
        EXPECT_EQ(run.output.rfind("chcrt: error: ", 0), 0u) << args << ": " << run.output;
        EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << args << ": " << run.output;
    }
    const CliRun info = chcrt(dir.file(""), "info --scene half.chs"); // prints the GL information first
    EXPECT_EQ(info.exitCode, 2) << info.output;
    EXPECT_NE(info.output.find("chcrt: error: "), std::string::npos) << info.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("big.chs")));
    EXPECT_FALSE(std::filesystem::exists(dir.file("big.chs.tmp")));
    EXPECT_FALSE(std::filesystem::exists(dir.file("x.png")));
}

} // namespace
} // namespace chcrt
