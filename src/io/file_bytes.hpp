#pragma once
// Internal to io/: the whole file in memory with one bulk read (DESIGN.md "read 1.3 M-point PLY: one bulk read").
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace ewis::io_detail {

// The file mapped read-only (no copy: the page cache is the buffer), or read into memory when it cannot be
// mapped (pipes, special files systems).
class FileBytes {
 public:
  FileBytes() = default;
  FileBytes(FileBytes&& o) noexcept { *this = std::move(o); }
  FileBytes& operator=(FileBytes&& o) noexcept;
  FileBytes(const FileBytes&) = delete;
  FileBytes& operator=(const FileBytes&) = delete;
  ~FileBytes();

  std::string_view view() const { return {ptr_, size_}; }
  std::size_t size() const { return size_; }

 private:
  friend FileBytes read_file_bytes(const std::string& path);
  const char* ptr_ = nullptr;
  std::size_t size_ = 0;
  void* mapped_ = nullptr;           // munmap on destruction when set
  std::unique_ptr<char[]> buffer_;   // otherwise the bytes live here
};

// Throws InputError(path, ...) for a missing or unreadable file, a directory, or an empty file.
FileBytes read_file_bytes(const std::string& path);

}  // namespace ewis::io_detail
