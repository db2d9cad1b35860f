#include <gtest/gtest.h>

#include <fstream>
#include <sys/stat.h>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"

using namespace ikebana;
using namespace ikebana::assets;

// Every JSON reader goes through one door: nothing nlohmann throws escapes it (a fuzzer's finding: a
// number too large for a double aborted `species check` and `sim --scene`).
TEST(JsonChecker, ANumberTooLargeForADoubleIsAProblemNamingTheFile) {
    JsonChecker c("overflow.json");
    EXPECT_FALSE(c.parse("{\"length_mm\": 1e400}"));
    ASSERT_EQ(c.problems().size(), 1u);
    EXPECT_EQ(c.problems()[0], "overflow.json: not valid JSON: number overflow parsing '1e400'");
}

TEST(JsonChecker, NestingBeyondTheLimitIsRefusedWithItsPlace) {
    JsonChecker c("deep.json");
    const std::string deep = "{\"a\":\n  " + std::string(200, '[') + std::string(200, ']') + "}";
    EXPECT_FALSE(c.parse(deep));
    ASSERT_EQ(c.problems().size(), 1u);
    EXPECT_EQ(c.problems()[0], "deep.json:2:66: arrays and objects nest deeper than 64 levels");
    JsonChecker ok("fine.json");
    EXPECT_TRUE(ok.parse("{\"a\": \"[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[\"}")) << "brackets in strings do not count";
}

// Only regular files are read, and only so much: /dev/zero or a FIFO would never end.
TEST(JsonChecker, OnlyRegularFilesWithinTheLimitAreRead) {
    const auto zero = read_text_file("/dev/zero");
    ASSERT_FALSE(zero);
    EXPECT_EQ(zero.error().message, "/dev/zero: not a regular file (a device, a FIFO or a socket is never read)");
    const auto fifo = std::filesystem::temp_directory_path() / "ikebana_fifo_test";
    std::filesystem::remove(fifo);
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_FALSE(read_text_file(fifo)) << "a FIFO is refused before it is opened (opening it would block)";
    std::filesystem::remove(fifo);
    const auto big = std::filesystem::temp_directory_path() / "ikebana_big_test.json";
    std::ofstream(big) << std::string(2048, ' ');
    const auto refused = read_text_file(big, 1024);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("2048 bytes"), std::string::npos) << refused.error().message;
    EXPECT_TRUE(read_text_file(big, 4096));
    std::filesystem::remove(big);
}
