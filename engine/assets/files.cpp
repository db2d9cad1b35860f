#include "engine/assets/files.hpp"

#include <cerrno>
#include <cstring>
#include <streambuf>
#include <string>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace ikebana::assets {

namespace {
Error os_error(const std::filesystem::path& path, const char* doing, int err) {
    return make_error(ErrorCode::io_error, path.string() + ": " + doing + " (" + std::strerror(err) + ")");
}

// Closes a descriptor on every path out of a function.
struct Descriptor {
    int fd = -1;
    explicit Descriptor(int f) : fd(f) {}
    Descriptor(const Descriptor&) = delete;
    Descriptor& operator=(const Descriptor&) = delete;
    ~Descriptor() {
        if (fd >= 0) ::close(fd);
    }
    int release() { return std::exchange(fd, -1); }
};

bool write_all(int fd, const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        data += n;
        size -= static_cast<std::size_t>(n);
    }
    return true;
}

const char* kind_of(mode_t mode) {
    if (S_ISLNK(mode)) return "a symbolic link";
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

// A 64 KiB output buffer: full or flushed (sync), it is drained, by writing or by handing it over.
class ChunkBuffer : public std::streambuf {
public:
    ChunkBuffer() { setp(buffer_, buffer_ + sizeof buffer_); }
    ChunkBuffer(const ChunkBuffer&) = delete;
    ChunkBuffer& operator=(const ChunkBuffer&) = delete;

protected:
    // False when the bytes (or earlier ones) could not be written.
    virtual bool drain(const char* data, std::size_t size) = 0;
    int_type overflow(int_type c) override {
        if (sync() != 0) return traits_type::eof();
        if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
        *pptr() = traits_type::to_char_type(c);
        pbump(1);
        return c;
    }
    int sync() override {
        const bool ok = drain(pbase(), static_cast<std::size_t>(pptr() - pbase()));
        setp(buffer_, buffer_ + sizeof buffer_);
        return ok ? 0 : -1;
    }

private:
    char buffer_[1 << 16];
};

// A buffered ostream over a descriptor it owns; flush() (sync) writes the buffer out.
class DescriptorBuffer final : public ChunkBuffer {
public:
    explicit DescriptorBuffer(int fd) : fd_(fd) {}
    ~DescriptorBuffer() override {
        sync();
        ::close(fd_);
    }

protected:
    bool drain(const char* data, std::size_t size) override { return write_all(fd_, data, size); }

private:
    int fd_;
};

template <typename Buffer>
class DescriptorStream final : public std::ostream {
public:
    explicit DescriptorStream(int fd) : std::ostream(nullptr), buffer_(fd) { rdbuf(&buffer_); }

private:
    Buffer buffer_;
};

// Created or truncated in place, never through a symbolic link, never a device or FIFO.
Result<int> open_for_writing(const std::filesystem::path& path) {
    if (auto ok = check_output_path(path); !ok) return std::move(ok).error();
    // O_NOFOLLOW: a link planted after the check is refused; O_NONBLOCK: a FIFO cannot hang the open.
    Descriptor file(::open(path.c_str(), O_WRONLY | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0644));
    if (file.fd < 0) return os_error(path, "cannot be opened for writing", errno);
    struct stat info {};
    if (::fstat(file.fd, &info) != 0) return os_error(path, "cannot be examined", errno);
    if (!S_ISREG(info.st_mode)) {
        return make_error(ErrorCode::io_error, path.string() + ": is " + kind_of(info.st_mode) + ", not a file; refusing to write to it");
    }
    if (::ftruncate(file.fd, 0) != 0) return os_error(path, "cannot be truncated", errno);
    if (::fcntl(file.fd, F_SETFL, ::fcntl(file.fd, F_GETFL) & ~O_NONBLOCK) != 0) return os_error(path, "cannot be set up", errno);
    return file.release();
}
} // namespace

Result<std::string> read_text_file(const std::filesystem::path& path, std::uintmax_t max_bytes) {
    // Non-blocking, so that opening a FIFO with no writer returns at once; fstat then refuses it.
    Descriptor file(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
    if (file.fd < 0) {
        if (errno == ENOENT || errno == ENOTDIR) return make_error(ErrorCode::not_found, path.string() + ": no such file");
        return os_error(path, "cannot be opened for reading", errno);
    }
    struct stat info {};
    if (::fstat(file.fd, &info) != 0) return os_error(path, "cannot be examined", errno);
    if (S_ISDIR(info.st_mode)) return make_error(ErrorCode::io_error, path.string() + ": is a directory");
    if (!S_ISREG(info.st_mode)) {
        return make_error(ErrorCode::io_error, path.string() + ": not a regular file (a device, a FIFO or a socket is never read)");
    }
    const auto too_big = [&](std::uintmax_t size) {
        return make_error(ErrorCode::io_error, path.string() + ": " + std::to_string(size) + " bytes, more than the " +
                                                   std::to_string(max_bytes >> 20) + " MiB a file may have here");
    };
    if (static_cast<std::uintmax_t>(info.st_size) > max_bytes) return too_big(static_cast<std::uintmax_t>(info.st_size));
    std::string text;
    text.reserve(static_cast<std::size_t>(info.st_size));
    char chunk[1 << 16];
    for (;;) {
        const ssize_t n = ::read(file.fd, chunk, sizeof chunk);
        if (n < 0) {
            if (errno == EINTR) continue;
            return os_error(path, "read failed", errno);
        }
        if (n == 0) break;
        text.append(chunk, static_cast<std::size_t>(n));
        if (text.size() > max_bytes) return too_big(text.size());
    }
    return text;
}

Result<void> check_output_path(const std::filesystem::path& path) {
    struct stat info {};
    if (::lstat(path.c_str(), &info) == 0) {
        if (S_ISREG(info.st_mode)) return {};
        return make_error(ErrorCode::io_error, path.string() + ": is " + kind_of(info.st_mode) + ", not a file; refusing to write to it");
    }
    if (errno != ENOENT) return os_error(path, "cannot be examined", errno);
    const auto folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec)) {
        return make_error(ErrorCode::not_found, path.string() + ": the folder " + folder.string() + " does not exist");
    }
    return {};
}

namespace {
// Writes `bytes` to a new temporary beside `path` (see write_file_atomically) and returns its name.
Result<std::string> write_temporary(const std::filesystem::path& path, std::string_view bytes);
} // namespace

Result<void> write_file_atomically(const std::filesystem::path& path, std::string_view bytes) {
    if (path.empty()) return make_error(ErrorCode::invalid_argument, "an output file's name is empty");
    auto temporary = write_temporary(path, bytes);
    if (!temporary) return std::move(temporary).error();
    if (::rename(temporary->c_str(), path.c_str()) != 0) {
        const int err = errno;
        ::unlink(temporary->c_str());
        return os_error(path, "cannot be replaced", err);
    }
    return {};
}

namespace {
Result<std::string> write_temporary(const std::filesystem::path& path, std::string_view bytes) {
    if (auto ok = check_output_path(path); !ok) return std::move(ok).error();
    const auto folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    // mkstemp creates the name with O_CREAT|O_EXCL: a file or link planted at a predictable
    // temporary name is never written through.
    std::string name = (folder / ("." + path.filename().string() + ".XXXXXX")).string();
    Descriptor file(::mkstemp(name.data()));
    if (file.fd < 0) return os_error(path, "cannot create a temporary file beside it", errno);
    const auto fail = [&](const char* doing) {
        const int err = errno;
        ::unlink(name.c_str());
        return os_error(path, doing, err);
    };
    // mkstemp makes 0600; an output is as readable as any file the user creates (or keeps the
    // mode of the file it replaces).
    struct stat old {};
    const mode_t mode = ::stat(path.c_str(), &old) == 0 ? (old.st_mode & 07777) : 0644;
    if (::fchmod(file.fd, mode) != 0) return fail("cannot set the temporary file's mode");
    if (!write_all(file.fd, bytes.data(), bytes.size())) return fail("cannot be written");
    if (::fsync(file.fd) != 0) return fail("cannot be written to disk");
    if (::close(file.release()) != 0) return fail("cannot be written");
    return name;
}
} // namespace

Result<void> write_text_file(const std::filesystem::path& path, const std::string& text) {
    return write_file_atomically(path, text);
}

Result<std::unique_ptr<std::ostream>> open_output_stream(const std::filesystem::path& path) {
    auto fd = open_for_writing(path);
    if (!fd) return std::move(fd).error();
    return std::unique_ptr<std::ostream>(std::make_unique<DescriptorStream<DescriptorBuffer>>(*fd));
}

std::filesystem::file_time_type last_changed(const std::filesystem::path& path) {
    std::error_code ec;
    const auto t = std::filesystem::last_write_time(path, ec);
    return ec ? std::filesystem::file_time_type::min() : t;
}

Result<void> create_output_folder(const std::filesystem::path& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (std::filesystem::is_directory(status)) return {};
    if (std::filesystem::exists(status)) {
        return make_error(ErrorCode::io_error, path.string() + ": exists and is not a folder");
    }
    std::filesystem::create_directories(path, ec);
    if (ec) return make_error(ErrorCode::io_error, path.string() + ": cannot create the folder (" + ec.message() + ")");
    return {};
}

OutputBatch::~OutputBatch() {
    if (committed_) return;
    for (const auto& staged : staged_) ::unlink(staged.temporary.c_str());
    // Innermost first; a folder something else has put a file in meanwhile is kept (remove() of a
    // folder that is not empty fails).
    std::error_code ec;
    for (auto it = made_folders_.rbegin(); it != made_folders_.rend(); ++it) std::filesystem::remove(*it, ec);
}

Result<void> OutputBatch::folder(const std::filesystem::path& path) {
    // The folders create_directories would make, outermost first.
    std::vector<std::filesystem::path> missing;
    std::error_code ec;
    for (auto p = path; !p.empty() && !std::filesystem::exists(std::filesystem::symlink_status(p, ec)); p = p.parent_path()) {
        missing.insert(missing.begin(), p);
        if (p == p.parent_path()) break;
    }
    if (auto made = create_output_folder(path); !made) return made;
    made_folders_.insert(made_folders_.end(), missing.begin(), missing.end());
    return {};
}

Result<void> OutputBatch::add(const std::filesystem::path& path, std::string_view bytes) {
    if (path.empty()) return make_error(ErrorCode::invalid_argument, "an output file's name is empty");
    for (const auto& staged : staged_) {
        if (staged.target == path) return make_error(ErrorCode::invalid_argument, path.string() + ": named twice as an output");
    }
    auto temporary = write_temporary(path, bytes);
    if (!temporary) return std::move(temporary).error();
    staged_.push_back({path, std::move(temporary).value()});
    return {};
}

Result<void> OutputBatch::commit() {
    for (std::size_t i = 0; i < staged_.size(); ++i) {
        if (::rename(staged_[i].temporary.c_str(), staged_[i].target.c_str()) != 0) {
            const int err = errno;
            staged_.erase(staged_.begin(), staged_.begin() + static_cast<std::ptrdiff_t>(i)); // those are in place
            return os_error(staged_.front().target, "cannot be replaced", err);
        }
    }
    staged_.clear();
    committed_ = true;
    return {};
}

} // namespace ikebana::assets
