#pragma once
#include <string_view>
#include <vector>
// Internal to io/: allocation-free tokenising and number parsing with std::from_chars (no streams, no locale).
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <type_traits>
#include <string>
#include <string_view>

namespace ewis::io_detail {

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

// The white-space separated words of a header line (views into `line`).
inline std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t b = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > b) words.push_back(line.substr(b, i - b));
  }
  return words;
}

// Parses the whole token as a number ("1", "-2.5e3", "+4", "nan", "inf"); false when anything is left over.
template <class T>
inline bool parse_number(std::string_view tok, T& out) {
  const char* b = tok.data();
  const char* e = b + tok.size();
  if (b != e && *b == '+') ++b;  // from_chars rejects a leading '+', text files use it
  if (b == e) return false;
  std::from_chars_result r;
  if constexpr (std::is_floating_point_v<T>) r = std::from_chars(b, e, out, std::chars_format::general);
  else r = std::from_chars(b, e, out);
  if constexpr (std::is_floating_point_v<T>) {
    if (r.ec == std::errc::result_out_of_range && r.ptr == e) {
      // 1e999 or 1e-999: a number out of range, not garbage: strtod gives +-inf or the underflowed value.
      char buf[128];
      const std::size_t len = static_cast<std::size_t>(e - b);
      if (len >= sizeof(buf)) return false;
      std::memcpy(buf, b, len);
      buf[len] = 0;
      if constexpr (std::is_same_v<T, float>) out = std::strtof(buf, nullptr);
      else out = static_cast<T>(std::strtod(buf, nullptr));
      return true;
    }
  }
  return r.ec == std::errc() && r.ptr == e;
}

// Whitespace-separated tokens over a buffer, counting lines for error messages.
struct TokenCursor {
  const char* p = nullptr;
  const char* end = nullptr;
  std::size_t line = 1;

  TokenCursor(const char* begin, const char* e, std::size_t first_line) : p(begin), end(e), line(first_line) {}
  bool next(std::string_view& tok) {
    while (p != end && is_space(*p)) {
      if (*p == '\n') ++line;
      ++p;
    }
    if (p == end) return false;
    const char* b = p;
    while (p != end && !is_space(*p)) ++p;
    tok = std::string_view(b, static_cast<std::size_t>(p - b));
    return true;
  }
};

// A short printable excerpt of a token for error messages.
inline std::string excerpt(std::string_view tok) {
  std::string s(tok.substr(0, 32));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return s;
}

}  // namespace ewis::io_detail
