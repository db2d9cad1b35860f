#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <future>
#include <thread>

#include <sys/stat.h>
#include <unistd.h>

#include "engine/assets/files.hpp"

using namespace ikebana;
using namespace ikebana::assets;
namespace fs = std::filesystem;

namespace {
// A fresh folder per test: outputs, links and FIFOs planted in it.
struct Folder {
    fs::path path;
    explicit Folder(const std::string& name) : path(fs::temp_directory_path() / ("ikebana_files_" + name)) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~Folder() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
    [[nodiscard]] fs::path operator/(const std::string& name) const { return path / name; }
};

std::string contents(const fs::path& p) {
    std::ifstream in(p);
    return {std::istreambuf_iterator<char>(in), {}};
}
} // namespace

TEST(Files, AWriteReplacesAFileWhole) {
    Folder dir("replace");
    ASSERT_TRUE(write_text_file(dir / "out.txt", "old"));
    ASSERT_TRUE(write_text_file(dir / "out.txt", "new"));
    EXPECT_EQ(contents(dir / "out.txt"), "new");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator{}), 1) << "no temporary file is left behind";
}

TEST(Files, AnOutputThatIsALinkIsRefusedAndTheLinkAndItsTargetKept) {
    Folder dir("link");
    std::ofstream(dir / "precious") << "keep";
    fs::create_symlink(dir / "precious", dir / "out.txt");
    const auto w = write_text_file(dir / "out.txt", "overwritten");
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error().message, (dir / "out.txt").string() + ": is a symbolic link, not a file; refusing to write to it");
    EXPECT_TRUE(fs::is_symlink(dir / "out.txt"));
    EXPECT_EQ(contents(dir / "precious"), "keep");
    const auto stream = open_output_stream(dir / "out.txt");
    ASSERT_FALSE(stream);
    EXPECT_EQ(contents(dir / "precious"), "keep");
}

TEST(Files, APlantedTemporaryLinkIsNeverWrittenThrough) {
    // The old writer wrote OUT.tmp and renamed it: a link planted at OUT.tmp overwrote its target.
    Folder dir("planted");
    std::ofstream(dir / "victim") << "keep";
    fs::create_symlink(dir / "victim", dir / "out.txt.tmp");
    ASSERT_TRUE(write_text_file(dir / "out.txt", "result"));
    EXPECT_EQ(contents(dir / "victim"), "keep");
    EXPECT_EQ(contents(dir / "out.txt"), "result");
    EXPECT_TRUE(fs::is_symlink(dir / "out.txt.tmp")) << "the planted link is left alone";
}

TEST(Files, DevicesFifosAndFoldersAreNeverOutputs) {
    Folder dir("special");
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
    fs::create_directories(dir / "folder");
    for (const auto& [path, kind] : {std::pair{fs::path("/dev/null"), "a device"}, std::pair{dir / "fifo", "a FIFO"},
                                     std::pair{dir / "folder", "a folder"}}) {
        const auto w = write_text_file(path, "x");
        ASSERT_FALSE(w) << path;
        EXPECT_EQ(w.error().message, path.string() + ": is " + kind + ", not a file; refusing to write to it");
        EXPECT_FALSE(open_output_stream(path)) << path;
    }
    EXPECT_TRUE(fs::is_character_file("/dev/null")) << "the device is still a device";
    EXPECT_TRUE(fs::is_fifo(dir / "fifo"));
    const auto missing = write_text_file(dir / "no_such_folder" / "out.txt", "x");
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().message, (dir / "no_such_folder" / "out.txt").string() + ": the folder " + (dir / "no_such_folder").string() + " does not exist");
}


TEST(Files, DevicesAndFifosAreRefusedAsInputsWithoutBlocking) {
    Folder dir("inputs");
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
    // On its own thread, so that a regression blocks the test's future, not the suite.
    auto read = std::async(std::launch::async, [&] { return read_text_file(dir / "fifo"); });
    ASSERT_EQ(read.wait_for(std::chrono::seconds(5)), std::future_status::ready) << "opening a FIFO with no writer blocked";
    const auto fifo = read.get();
    ASSERT_FALSE(fifo);
    EXPECT_EQ(fifo.error().message, (dir / "fifo").string() + ": not a regular file (a device, a FIFO or a socket is never read)");
    const auto zero = read_text_file("/dev/zero");
    ASSERT_FALSE(zero);
    EXPECT_EQ(zero.error().message, "/dev/zero: not a regular file (a device, a FIFO or a socket is never read)");
    std::ofstream(dir / "big") << std::string(2000, 'x');
    const auto big = read_text_file(dir / "big", 1000);
    ASSERT_FALSE(big);
    EXPECT_EQ(big.error().message, (dir / "big").string() + ": 2000 bytes, more than the 0 MiB a file may have here");
}

TEST(Files, AStreamedOutputReachesTheDiskAtEachFlush) {
    Folder dir("stream");
    auto out = open_output_stream(dir / "log.csv");
    ASSERT_TRUE(out) << out.error().message;
    **out << "header\n" << std::flush;
    EXPECT_EQ(contents(dir / "log.csv"), "header\n") << "a crash after the flush keeps what was flushed";
    **out << "row\n";
    out->reset();
    EXPECT_EQ(contents(dir / "log.csv"), "header\nrow\n");
}

TEST(Files, AnOutputFolderThatIsAFileIsRefused) {
    Folder dir("folder");
    std::ofstream(dir / "file") << "x";
    const auto r = create_output_folder(dir / "file");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message, (dir / "file").string() + ": exists and is not a folder");
    EXPECT_TRUE(create_output_folder(dir / "a" / "b"));
    EXPECT_TRUE(fs::is_directory(dir / "a" / "b"));
}

// A command's outputs, all or none: staged outputs are not there until commit; a batch dropped
// without commit (the command failed at its third output) leaves no file, no temporary and no folder
// it made, and the files that were there before are as they were.
TEST(Files, AnOutputBatchWritesAllOrNone) {
    Folder dir("batch");
    ASSERT_TRUE(write_text_file(dir / "old.json", "old"));
    {
        OutputBatch batch;
        ASSERT_TRUE(batch.folder(dir / "report" / "deep"));
        ASSERT_TRUE(batch.add(dir / "old.json", "new"));
        ASSERT_TRUE(batch.add(dir / "report" / "deep" / "report.md", "# report"));
        fs::create_symlink(dir / "old.json", dir / "report" / "deep" / "figure.svg");
        const auto planted = batch.add(dir / "report" / "deep" / "figure.svg", "<svg/>");
        ASSERT_FALSE(planted);
        EXPECT_NE(planted.error().message.find("figure.svg: is a symbolic link"), std::string::npos) << planted.error().message;
        EXPECT_EQ(contents(dir / "old.json"), "old") << "nothing is in place before commit";
        fs::remove(dir / "report" / "deep" / "figure.svg");
    }
    EXPECT_EQ(contents(dir / "old.json"), "old");
    EXPECT_FALSE(fs::exists(dir / "report")) << "the folders the batch made went with it";
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator{}), 1) << "no temporary is left";
    OutputBatch batch;
    ASSERT_TRUE(batch.folder(dir / "report"));
    ASSERT_TRUE(batch.add(dir / "old.json", "new"));
    ASSERT_TRUE(batch.add(dir / "report" / "report.md", "# report"));
    ASSERT_TRUE(batch.commit());
    EXPECT_EQ(contents(dir / "old.json"), "new");
    EXPECT_EQ(contents(dir / "report" / "report.md"), "# report");
}
