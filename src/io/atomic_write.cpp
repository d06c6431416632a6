// write_file_atomic: the whole file under a temporary name in the same directory, then rename(2), so a reader
// (or a failed run) never sees a half-written file (CONTRACT.md "Exit codes and errors"). No fsync: the
// guarantee is against crashes of this program and concurrent readers, not power loss, and a campaign writes
// hundreds of files (fsync cost ~10-50 ms each on the VM disks measured).
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <thread>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"

namespace ewis {

namespace {

// A temporary file next to `path`, renamed onto it by commit(); removed when not committed.
class AtomicFile {
 public:
  explicit AtomicFile(const std::string& path) : path_(path) {
    if (path.empty()) throw InputError(path, "empty output file name");
    // Unique per process, thread and moment: parallel writers of different files never share a temporary.
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    const std::size_t tid = std::hash<std::thread::id>{}(std::this_thread::get_id());
    tmp_ = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(tid % 100000) + "." +
           std::to_string(stamp % 1000000000);
    fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd_ < 0) throw InputError(path, std::string("cannot write: ") + std::strerror(errno));
  }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) ::unlink(tmp_.c_str());
  }

  void write(const void* data, std::size_t size) {
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
      const ssize_t n = ::write(fd_, p, size);
      if (n < 0) {
        if (errno == EINTR) continue;
        fail(errno);
      }
      p += n, size -= static_cast<std::size_t>(n);
    }
  }

  void commit() {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) fail(errno);
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0) fail(errno);
    committed_ = true;
  }

 private:
  [[noreturn]] void fail(int err) { throw InputError(path_, std::string("cannot write: ") + std::strerror(err)); }

  std::string path_, tmp_;
  int fd_ = -1;
  bool committed_ = false;
};

}  // namespace

void write_file_atomic(const std::string& path, const void* data, std::size_t size) {
  AtomicFile f(path);
  f.write(data, size);
  f.commit();
}

void write_file_atomic_chunked(const std::string& path, const std::function<bool(std::string&)>& next) {
  AtomicFile f(path);
  std::string chunk;
  for (bool more = true; more;) {
    chunk.clear();
    more = next(chunk);
    f.write(chunk.data(), chunk.size());
  }
  f.commit();
}

void write_file_atomic(const std::string& path, const std::string& contents) {
  write_file_atomic(path, contents.data(), contents.size());
}

}  // namespace ewis
