#pragma once
// Errors a user can cause (bad files, bad options): the CLI prints "<file>: <what>" and exits 2.
#include <stdexcept>
#include <string>

namespace ewis {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, const std::string& what)
      : std::runtime_error(file.empty() ? what : file + ": " + what), file_(std::move(file)) {}
  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

// The program could not finish (e.g. registration did not converge): exit code 3.
class ProcessingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ewis
