#pragma once
// The program's one door to the file system for a user's paths, in and out. A user (or someone who
// planted a file where the user will write) may name a device, a FIFO, a symbolic link or a folder
// where a file is expected; each is refused with the path in the message, before anything blocks,
// grows without bound or is written through.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/result.hpp"

namespace ikebana::assets {

inline constexpr std::uintmax_t max_text_file_bytes = 64ull << 20; // 64 MiB

// Reads a whole regular file of at most `max_bytes`; not_found or io_error naming the path. Devices,
// FIFOs and directories are refused without blocking (the file is opened non-blocking and checked
// with fstat, so a FIFO swapped in after a check is refused too); a file that grows while it is
// read is cut off at the limit and refused.
Result<std::string> read_text_file(const std::filesystem::path& path, std::uintmax_t max_bytes = max_text_file_bytes);

// Whether `path` may be written as an output: missing, or an existing regular file that is not a
// symbolic link, in an existing folder. Refusals name the path and what it is.
Result<void> check_output_path(const std::filesystem::path& path);

// Writes `bytes` to a new, exclusively created temporary file beside `path` (mkstemp: never an
// existing name, never through a symbolic link) and renames it over `path`: a reader sees the old
// file or the whole new one, and a refused or failed write leaves no trace. `path` must pass
// check_output_path.
Result<void> write_file_atomically(const std::filesystem::path& path, std::string_view bytes);
Result<void> write_text_file(const std::filesystem::path& path, const std::string& text);

// A log written as it goes (a device recording): created or truncated in place, never through a
// symbolic link, never a device or FIFO. Data reaches the file at each flush(), so a crash loses at
// most what came after the last one.
Result<std::unique_ptr<std::ostream>> open_output_stream(const std::filesystem::path& path);
// (The 1 kHz loop never writes to one itself: it hands lines to an AsyncLineWriter, whose thread does.)

// When the file was last written; the earliest time there is when it cannot be read (gone, mid-save),
// so that a watcher sees any later save as a change.
[[nodiscard]] std::filesystem::file_time_type last_changed(const std::filesystem::path& path);

// Creates the folder (and its parents) that outputs go to; refuses a path that exists and is not a
// folder (or a link to one).
Result<void> create_output_folder(const std::filesystem::path& path);

// The files one command writes, all or none. Each is checked (check_output_path) and written to a
// temporary beside its target as it is added; commit() renames them over their targets. Destroyed
// without commit() (the command failed after some of its outputs were ready: a planted link where
// the report goes), it removes the temporaries and the folders it made, so a failed command leaves
// what was there before. (The renames themselves are one system call each, after every write has
// succeeded: the only step left that can fail half-way, and it does not in one folder of one disk.)
class OutputBatch {
public:
    OutputBatch() = default;
    OutputBatch(const OutputBatch&) = delete;
    OutputBatch& operator=(const OutputBatch&) = delete;
    ~OutputBatch();
    // A folder outputs go to (create_output_folder), remembered if this made it.
    Result<void> folder(const std::filesystem::path& path);
    Result<void> add(const std::filesystem::path& path, std::string_view bytes);
    Result<void> commit();

private:
    struct Staged {
        std::filesystem::path target;
        std::string temporary;
    };
    std::vector<Staged> staged_;
    std::vector<std::filesystem::path> made_folders_; // outermost first
    bool committed_ = false;
};

} // namespace ikebana::assets
