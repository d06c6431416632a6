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

void write_file_atomic(const std::string& path, const void* data, std::size_t size) {
  if (path.empty()) throw InputError(path, "empty output file name");
  // Unique per process, thread and moment: parallel writers of different files never share a temporary.
  const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
  const std::size_t tid = std::hash<std::thread::id>{}(std::this_thread::get_id());
  const std::string tmp = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(tid % 100000) + "." +
                          std::to_string(stamp % 1000000000);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(path, std::string("cannot write: ") + std::strerror(errno));
  const char* p = static_cast<const char*>(data);
  std::size_t left = size;
  int err = 0;
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      err = errno;
      break;
    }
    p += n, left -= static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0 && !err) err = errno;
  if (!err && std::rename(tmp.c_str(), path.c_str()) != 0) err = errno;
  if (err) {
    ::unlink(tmp.c_str());
    throw InputError(path, std::string("cannot write: ") + std::strerror(err));
  }
}

void write_file_atomic(const std::string& path, const std::string& contents) {
  write_file_atomic(path, contents.data(), contents.size());
}

}  // namespace ewis
