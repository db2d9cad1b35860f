// libFuzzer: the recording writer (AsyncLineWriter, every device sample, command and recording line
// goes through it) onto a disk that fills up. The first two bytes are how many bytes the "disk" takes
// before it refuses (a full disk: every write after that fails), the third picks drop or wait when the
// ring is full and a small ring; the rest are the lines, split at '\n'. Whatever the lines and wherever
// the disk fills, the writer must end, say it failed exactly when a line did not fit (once, in words),
// and what reached the disk must be the start of what was queued: no garbled, reordered or late bytes.
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <streambuf>
#include <string>

#include "engine/core/async_line_writer.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

namespace {

// A disk of `room` bytes: what fits is kept, the rest refused (the stream goes bad, as on ENOSPC).
class FullDisk : public std::streambuf {
public:
    explicit FullDisk(std::size_t room) : room_(room) {}
    const std::string& kept() const { return kept_; }

protected:
    std::streamsize xsputn(const char* s, std::streamsize n) override {
        const auto fits = static_cast<std::streamsize>(std::min<std::size_t>(static_cast<std::size_t>(n), room_ - kept_.size()));
        kept_.append(s, static_cast<std::size_t>(fits));
        return fits;
    }
    int_type overflow(int_type ch) override {
        if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
        if (kept_.size() >= room_) return traits_type::eof();
        kept_.push_back(traits_type::to_char_type(ch));
        return ch;
    }

private:
    std::size_t room_;
    std::string kept_;
};

[[noreturn]] void finding(const char* what) {
    std::fprintf(stderr, "%s\n", what);
    std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 3) return 0;
    const std::size_t room = static_cast<std::size_t>(data[0]) | (static_cast<std::size_t>(data[1]) << 8);
    const auto when_full = (data[2] & 1) != 0 ? AsyncLineWriter::WhenFull::wait : AsyncLineWriter::WhenFull::drop;
    const std::size_t capacity = 2 + (data[2] >> 1);
    FullDisk disk(room);
    std::ostream out(&disk);
    std::string queued; // every line the writer took, in order
    int told = 0;
    std::string words;
    {
        AsyncLineWriter writer(out, when_full, capacity, std::chrono::milliseconds(1));
        writer.on_failure([&](const std::string& why) {
            ++told;
            words = why;
        });
        const std::string_view text = fuzz::text_of(data + 3, size - 3);
        for (std::size_t at = 0; at < text.size();) {
            const std::size_t end = text.find('\n', at);
            const std::size_t stop = end == std::string_view::npos ? text.size() : end + 1;
            const std::string_view line = text.substr(at, stop - at);
            if (writer.write(line)) queued.append(line);
            at = stop;
        }
        writer.flush();
        if (writer.failed() != (queued.size() > room)) finding("said to fail when every line fit, or not when one did not");
        if (writer.failed() && writer.failure().empty()) finding("a failure without words");
    }
    if (queued.size() > room && told != 1) finding("a full disk was not told exactly once");
    if (queued.size() <= room && told != 0) finding("told of a failure when nothing failed");
    const std::string& kept = disk.kept();
    if (kept.size() > room || queued.compare(0, kept.size(), kept) != 0) finding("what reached the disk is not the start of what was queued");
    if (queued.size() <= room && kept != queued) finding("a disk with room did not get every line");
    return 0;
}
