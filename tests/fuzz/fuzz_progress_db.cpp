// libFuzzer: the progress database (`ikebana history`, and the app and `lesson demo` that store into
// it) opened on arbitrary bytes as the file. A reader refuses with the file's name or reads sessions
// whole; a writer that refuses leaves every byte as it was, and one that accepts stores a session it
// then reads back.
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

#include "game/progress/progress_db.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

namespace {

std::filesystem::path folder() {
    static const auto dir = [] {
        auto d = std::filesystem::temp_directory_path() / ("ikebana-fuzz-progress-" + std::to_string(getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir;
}

std::string bytes_of(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // The file's name carries the label, so a refusal that names the file names the input.
    const auto path = folder() / (std::string(fuzz::label) + ".sqlite");
    for (const char* extra : {"", "-wal", "-shm", "-journal"}) std::filesystem::remove(path.string() + extra);
    {
        std::ofstream out(path, std::ios::binary);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    {
        auto reader = game::ProgressDb::open_read_only(path);
        fuzz::expect_named(reader);
        if (reader) fuzz::expect_named(reader->sessions());
    }
    const std::string before = bytes_of(path);
    auto writer = game::ProgressDb::open(path);
    fuzz::expect_named(writer);
    if (!writer) {
        if (bytes_of(path) != before) {
            std::fprintf(stderr, "a refused database was written to\n");
            std::abort();
        }
        return 0;
    }
    game::SessionRecord s;
    s.lesson = "sogetsu_basic_upright";
    s.trainee = "fuzz";
    s.started_unix_s = 1;
    s.result.score = 50.0;
    s.result.criteria.push_back({"shin", "tilt_deg", 15.0, 10.0, 30.0, 10.0, 30.0, "tip"});
    auto saved = writer->save(s);
    fuzz::expect_named(saved);
    if (saved) {
        auto all = writer->sessions();
        fuzz::expect_named(all);
        // What was stored is read back whole, unless the file's damage hides it (a session read as
        // it was written, or a refusal that names the file: never a half session).
        if (all) {
            bool found = false;
            for (const auto& r : *all) found = found || (r.id == s.id && r.result.criteria.size() == 1 && r.trainee == "fuzz");
            if (!found) {
                std::fprintf(stderr, "a stored session is not read back\n");
                std::abort();
            }
        }
    }
    return 0;
}
