#include "renderer/core/error.h"
#include "renderer/core/frame_range.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

using Frames = std::vector<int>;

TEST(FrameRange, SingleFrame) {
    EXPECT_EQ(parseFrameRange("7"), Frames({7}));
    EXPECT_EQ(parseFrameRange("0"), Frames({0}));
}

TEST(FrameRange, InclusiveRange) {
    EXPECT_EQ(parseFrameRange("1-5"), Frames({1, 2, 3, 4, 5}));
    EXPECT_EQ(parseFrameRange("4-4"), Frames({4}));
    const Frames all = parseFrameRange("1-100");
    ASSERT_EQ(all.size(), 100u);
    EXPECT_EQ(all.front(), 1);
    EXPECT_EQ(all.back(), 100);
}

TEST(FrameRange, Step) {
    EXPECT_EQ(parseFrameRange("1-100:10"), Frames({1, 11, 21, 31, 41, 51, 61, 71, 81, 91}));
    EXPECT_EQ(parseFrameRange("0-10:5"), Frames({0, 5, 10}));
    EXPECT_EQ(parseFrameRange("3-4:100"), Frames({3}));
}

TEST(FrameRange, ListsKeepOrderOfAppearance) {
    EXPECT_EQ(parseFrameRange("3,5-9"), Frames({3, 5, 6, 7, 8, 9}));
    EXPECT_EQ(parseFrameRange("9,1-2"), Frames({9, 1, 2}));
    EXPECT_EQ(parseFrameRange(" 3 , 5 - 6 "), Frames({3, 5, 6}));
}

TEST(FrameRange, DuplicatesRemovedFirstOccurrenceWins) {
    EXPECT_EQ(parseFrameRange("5,1-6"), Frames({5, 1, 2, 3, 4, 6}));
    EXPECT_EQ(parseFrameRange("2,2,2"), Frames({2}));
    EXPECT_EQ(parseFrameRange("1-4,3-6"), Frames({1, 2, 3, 4, 5, 6}));
    // Few frames spread wide (sorted with their positions rather than marked in a bitmap over their span).
    EXPECT_EQ(parseFrameRange("9999999,3,0-2,9999999,1"), Frames({9999999, 3, 0, 1, 2}));
}

TEST(FrameRange, MalformedInputThrowsWithTheText) {
    for (const char* text : {"", " ", "a", "5-3", "1-10:0", "-1", "1--3", "1,,2", ",1", "1,", "1.5", "1-", "-",
                             "1-5:", "1-5:x", "7:2", "1-2-3", "99999999999", "+3", "0-20000000"}) {
        try {
            parseFrameRange(text);
            ADD_FAILURE() << "no error for \"" << text << "\"";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("\"" + std::string(text) + "\""), std::string::npos)
                << e.what();
        }
    }
}

// Frame numbers stop at the longest walkthrough's last frame and selections at 10^7 frames, repeats counted,
// checked before anything is expanded; at the limits the list is made once and stays fast (tests/fuzz/).
TEST(FrameRange, LimitsHoldBeforeAnythingIsExpanded) {
    EXPECT_EQ(parseFrameRange("9999999"), Frames({9999999}));
    const Frames all = parseFrameRange("0-9999999");
    ASSERT_EQ(all.size(), 10'000'000u);
    EXPECT_EQ(all.back(), 9999999);
    const Frames interleaved = parseFrameRange("1-9999999:2,0-9999998:2");
    ASSERT_EQ(interleaved.size(), 10'000'000u);
    EXPECT_EQ(interleaved[4'999'999], 9999999);
    EXPECT_EQ(interleaved[5'000'000], 0);
    for (const char* text : {"10000000", "5-10000000", "0-9999999,0", "0-4999999,0-4999999,7"}) {
        EXPECT_THROW(parseFrameRange(text), InputError) << text;
    }
}

TEST(FrameRange, MessagesSayWhatIsWrong) {
    const auto message = [](const char* text) {
        try {
            parseFrameRange(text);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(message("5-3").find("reversed"), std::string::npos);
    EXPECT_NE(message("1-10:0").find("zero step"), std::string::npos);
    EXPECT_NE(message("1,,2").find("empty item"), std::string::npos);
    EXPECT_NE(message("-1").find("non-negative"), std::string::npos);
    EXPECT_NE(message("3-12345678").find("has 12345678 as its last frame, past the last frame a walkthrough may "
                                         "have (9999999)"),
              std::string::npos);
    EXPECT_NE(message("0-9999999,0").find("selects more than 10000000 frames"), std::string::npos);
}

TEST(FramePath, ReplacesLastRunOfHashes) {
    EXPECT_EQ(formatFramePath("out_####.png", 7, 100), "out_0007.png");
    EXPECT_EQ(formatFramePath("out_#.png", 7, 100), "out_7.png");
    EXPECT_EQ(formatFramePath("out_##.png", 12345, 20000), "out_12345.png"); // never truncated
    EXPECT_EQ(formatFramePath("a#/b_###.exr", 3, 10), "a#/b_003.exr");
    EXPECT_EQ(formatFramePath("####", 42, 1), "0042");
}

TEST(FramePath, WithoutHashes) {
    EXPECT_EQ(formatFramePath("out.png", 7, 1), "out.png");
    EXPECT_EQ(formatFramePath("out.png", 7, 100), "out_0007.png");
    EXPECT_EQ(formatFramePath("dir.v2/out.png", 7, 100), "dir.v2/out_0007.png");
    EXPECT_EQ(formatFramePath("out", 7, 100), "out_0007");
    EXPECT_EQ(formatFramePath("out.png", 7, 123456), "out_000007.png");
}

} // namespace
} // namespace chcrt
