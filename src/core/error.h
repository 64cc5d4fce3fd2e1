#pragma once
#include <stdexcept>
#include <string>

namespace lego {

// Bad input a user gave us, with the place it came from. app/ turns it into a message and an
// exit code; nothing below app/ exits.
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, const std::string& message)
      : std::runtime_error(format(file, line, message)), file_(std::move(file)), line_(line) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }

  static std::string format(const std::string& file, int line, const std::string& message) {
    if (file.empty()) return message;
    return line > 0 ? file + ":" + std::to_string(line) + ": " + message : file + ": " + message;
  }

 private:
  std::string file_;
  int line_;
};

}  // namespace lego
