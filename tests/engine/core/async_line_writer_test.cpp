// A file that refuses a write (a full disk) is noticed, said at once and remembered; the producer is
// never held by it.
#include <gtest/gtest.h>

#include <atomic>
#include <cerrno>
#include <ostream>
#include <streambuf>
#include <string>

#include "engine/core/async_line_writer.hpp"

using namespace ikebana;

namespace {
// Takes `room` bytes, then refuses as a full disk does.
class FullDisk final : public std::streambuf {
public:
    explicit FullDisk(std::size_t room) : room_(room) {}
    std::string taken;

protected:
    std::streamsize xsputn(const char* s, std::streamsize n) override {
        if (taken.size() + static_cast<std::size_t>(n) > room_) {
            errno = ENOSPC;
            return 0;
        }
        taken.append(s, static_cast<std::size_t>(n));
        return n;
    }
    int_type overflow(int_type c) override {
        if (traits_type::eq_int_type(c, traits_type::eof())) return 0;
        char ch = traits_type::to_char_type(c);
        return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
    }

private:
    std::size_t room_;
};
} // namespace

TEST(AsyncLineWriter, AFileThatRefusesAWriteIsSaidAtOnceRememberedAndHoldsNoProducer) {
    FullDisk disk(1000);
    std::ostream out(&disk);
    std::atomic<int> told{0};
    std::string why;
    {
        AsyncLineWriter writer(out, AsyncLineWriter::WhenFull::wait, 64);
        writer.on_failure([&](const std::string& w) {
            why = w;
            ++told;
        });
        for (int i = 0; i < 2000; ++i) ASSERT_TRUE(writer.write("a line of forty characters, give or take\n")) << i;
        writer.flush();
        EXPECT_TRUE(writer.failed());
        EXPECT_EQ(writer.failure(), "No space left on device");
    }
    EXPECT_EQ(told.load(), 1) << "said once, the moment it happened";
    EXPECT_EQ(why, "No space left on device");
    EXPECT_LE(disk.taken.size(), 1000u);
}

TEST(AsyncLineWriter, AFileWithRoomIsWrittenWholeAndNeverSaidToHaveFailed) {
    FullDisk disk(1 << 20);
    std::ostream out(&disk);
    {
        AsyncLineWriter writer(out, AsyncLineWriter::WhenFull::wait, 64);
        for (int i = 0; i < 100; ++i) ASSERT_TRUE(writer.write("0123456789\n"));
        writer.flush();
        EXPECT_FALSE(writer.failed());
        EXPECT_EQ(writer.failure(), "");
    }
    EXPECT_EQ(disk.taken.size(), 1100u);
}
