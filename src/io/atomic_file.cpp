#include "bushel/io/atomic_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <utility>

#include "bushel/core/input_error.hpp"

namespace bushel::io {
namespace {

std::string errno_text(int err) { return std::error_code(err, std::generic_category()).message(); }

// Closes the descriptor and removes the temporary file unless released, so that every early
// exit (a failed write, a failed rename) cleans up after itself.
class TemporaryFile {
 public:
  TemporaryFile(std::string name, int fd) : name_(std::move(name)), fd_(fd) {}
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  ~TemporaryFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!released_) ::unlink(name_.c_str());
  }
  int fd() const { return fd_; }
  const std::string& name() const { return name_; }
  /// Closes the descriptor; returns 0 or an errno value (close can report a failed write-back).
  int close() {
    const int rc = ::close(fd_);
    fd_ = -1;
    return rc == 0 ? 0 : errno;
  }
  void release() { released_ = true; }

 private:
  std::string name_;
  int fd_ = -1;
  bool released_ = false;
};

// ".<name>.tmp-<pid>-<n>" next to the target: the same directory, so the rename never crosses
// a file system; the pid and a counter keep concurrent writers (processes, threads) apart.
TemporaryFile open_temporary(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path dir = target.parent_path();
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string leaf =
        fmt::format(".{}.tmp-{}-{}", target.filename().string(), static_cast<long>(::getpid()), counter.fetch_add(1));
    std::string name = (dir / leaf).string();
    const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) return {std::move(name), fd};
    if (errno != EEXIST) {
      throw InputError(
          fmt::format("cannot create a temporary file in the directory of the output: {}", errno_text(errno)))
          .at(target.string());
    }
  }
  throw InputError("cannot create a temporary file in the directory of the output: all names are taken")
      .at(target.string());
}

}  // namespace

void write_file_atomically(const std::string& path, std::string_view content) {
  if (path.empty()) throw InputError("expected an output file name, got an empty one");
  const std::filesystem::path target(path);
  if (target.filename().empty()) throw InputError("expected an output file name, got a directory").at(path);
  TemporaryFile tmp = open_temporary(target);
  const char* data = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ::ssize_t n = ::write(tmp.fd(), data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw InputError(fmt::format("cannot write the file: {}", errno_text(errno))).at(path);
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  // The data must be on disk before the rename makes it visible under the final name;
  // otherwise a power cut could leave the new name pointing at an empty file.
  if (::fsync(tmp.fd()) != 0) {
    throw InputError(fmt::format("cannot flush the file to disk: {}", errno_text(errno))).at(path);
  }
  if (const int err = tmp.close(); err != 0) {
    throw InputError(fmt::format("cannot write the file: {}", errno_text(err))).at(path);
  }
  std::error_code ec;
  std::filesystem::rename(tmp.name(), target, ec);
  if (ec) throw InputError(fmt::format("cannot replace the file: {}", ec.message())).at(path);
  tmp.release();
}

}  // namespace bushel::io
