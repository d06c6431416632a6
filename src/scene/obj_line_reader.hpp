#pragma once
// Internal to the scene stage: the logical lines of a text file, read in chunks (nothing else is held).
// Line ends are '\n', '\r', '\0' and '\f' (Assimp's IsLineEnd, so CRLF gives an empty line after each line);
// a '\' right before a line end joins the next line without a separator, skipping up to the next '\n'
// (Assimp's IOStreamBuffer::getNextDataLine).
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace ewis::detail {

class ObjLineReader {
 public:
  explicit ObjLineReader(const std::string& path);  // throws InputError(path, ...) when it cannot be opened
  ~ObjLineReader();
  ObjLineReader(const ObjLineReader&) = delete;
  ObjLineReader& operator=(const ObjLineReader&) = delete;

  // The next logical line without its end, valid until the next call; false at the end of the file.
  bool next(std::string_view& line);
  // 1-based number of the physical line where the last returned line starts (counted at '\n').
  std::size_t line_number() const { return line_; }

 private:
  bool ensure(std::size_t k);  // makes buf_[pos_ + k] available; false at the end of the file

  std::string path_;
  std::FILE* file_ = nullptr;
  std::vector<char> buf_;
  std::size_t pos_ = 0, end_ = 0;
  bool eof_ = false;
  std::string joined_;  // a line continued with '\'
  std::size_t line_ = 0, next_line_ = 1;
};

}  // namespace ewis::detail
