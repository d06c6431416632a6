// Chunked logical-line reading for the OBJ reader: a 1 MiB buffer, grown only for a longer line.
#include "obj_line_reader.hpp"

#include <cstring>

#include "ewis/core/error.hpp"

namespace ewis::detail {
namespace {

bool line_end(char c) { return c == '\n' || c == '\r' || c == '\0' || c == '\f'; }

}  // namespace

ObjLineReader::ObjLineReader(const std::string& path)
    : path_(path), file_(std::fopen(path.c_str(), "rb")), buf_(std::size_t(1) << 20) {
  if (!file_) throw InputError(path, "cannot open file");
}

ObjLineReader::~ObjLineReader() { std::fclose(file_); }

bool ObjLineReader::ensure(std::size_t k) {
  while (pos_ + k >= end_) {
    if (eof_) return false;
    if (pos_ > 0) {  // keep the unread tail, drop what was returned
      std::memmove(buf_.data(), buf_.data() + pos_, end_ - pos_);
      end_ -= pos_;
      pos_ = 0;
    }
    if (end_ == buf_.size()) buf_.resize(buf_.size() * 2);  // one line longer than the buffer
    const std::size_t got = std::fread(buf_.data() + end_, 1, buf_.size() - end_, file_);
    if (got == 0) {
      if (std::ferror(file_)) throw InputError(path_, "cannot read file");
      eof_ = true;
    }
    end_ += got;
  }
  return true;
}

bool ObjLineReader::next(std::string_view& line) {
  // Most lines: the whole line and its end are in the buffer already, and no '\' in it (no continuation).
  {
    const char* const b = buf_.data() + pos_;
    const char* const e = buf_.data() + end_;
    const char* p = b;
    while (p < e && !line_end(*p) && *p != '\\') ++p;
    if (p < e && line_end(*p)) {
      line_ = next_line_;
      line = std::string_view(b, std::size_t(p - b));
      if (*p == '\n') ++next_line_;
      pos_ += std::size_t(p - b) + 1;
      return true;
    }
  }
  if (!ensure(0)) return false;
  line_ = next_line_;
  bool joined = false;
  std::size_t start = 0, k = 0;  // offsets from pos_ (ensure() may move the buffer's content)
  while (ensure(k)) {
    const char c = buf_[pos_ + k];
    if (line_end(c)) break;
    if (c == '\\' && ensure(k + 1) && line_end(buf_[pos_ + k + 1])) {
      if (!joined) joined_.clear();
      joined_.append(buf_.data() + pos_ + start, k - start);
      joined = true;
      for (++k; ensure(k) && buf_[pos_ + k] != '\n'; ++k) {
      }
      if (ensure(k)) ++next_line_;
      start = ++k;
      continue;
    }
    ++k;
  }
  const bool at_end = !ensure(k);
  const std::size_t stop = at_end ? end_ - pos_ : k;
  if (start > stop) start = stop;  // the file ended inside a continuation
  const std::string_view piece(buf_.data() + pos_ + start, stop - start);
  if (joined) {
    joined_.append(piece);
    line = joined_;
  } else {
    line = piece;
  }
  if (at_end) {
    pos_ = end_;
  } else {
    if (buf_[pos_ + k] == '\n') ++next_line_;
    pos_ += k + 1;
  }
  return true;
}

}  // namespace ewis::detail
