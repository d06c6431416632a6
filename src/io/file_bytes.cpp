#include "file_bytes.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "ewis/core/error.hpp"

namespace ewis::io_detail {

namespace {
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};
}  // namespace

FileBytes& FileBytes::operator=(FileBytes&& o) noexcept {
  if (this != &o) {
    if (mapped_) ::munmap(mapped_, size_);
    ptr_ = o.ptr_, size_ = o.size_, mapped_ = o.mapped_, buffer_ = std::move(o.buffer_);
    o.ptr_ = nullptr, o.size_ = 0, o.mapped_ = nullptr;
  }
  return *this;
}

FileBytes::~FileBytes() {
  if (mapped_) ::munmap(mapped_, size_);
}

FileBytes read_file_bytes(const std::string& path) {
  if (path.empty()) throw InputError(path, "empty file name");
  Fd f;
  f.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (f.fd < 0) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) throw InputError(path, std::string("cannot stat: ") + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw InputError(path, "is a directory, not a file");
  if (!S_ISREG(st.st_mode)) throw InputError(path, "not a regular file");
  if (st.st_size <= 0) throw InputError(path, "empty file");
  FileBytes out;
  const std::size_t size = static_cast<std::size_t>(st.st_size);
  // One mapping, populated up front: the readers then walk it like an array (DESIGN.md: one bulk read).
  void* m = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, f.fd, 0);
  if (m != MAP_FAILED) {
    out.mapped_ = m;
    out.ptr_ = static_cast<const char*>(m);
    out.size_ = size;
    return out;
  }
  out.buffer_.reset(new char[size]);
  std::size_t done = 0;
  while (done < size) {
    const ssize_t got = ::read(f.fd, out.buffer_.get() + done, size - done);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw InputError(path, std::string("cannot read: ") + std::strerror(errno));
    }
    if (got == 0) break;  // the file shrank while we read it
    done += static_cast<std::size_t>(got);
  }
  if (done == 0) throw InputError(path, "empty file");
  out.ptr_ = out.buffer_.get();
  out.size_ = done;
  return out;
}

}  // namespace ewis::io_detail
