#include "surfcap/core/error.hpp"

namespace surfcap::core {

std::string where(const std::filesystem::path& file, std::optional<long> frame) {
  std::string text = "'" + file.string() + "'";
  if (frame) text += " (frame " + std::to_string(*frame) + ")";
  return text;
}

Error bad_input(const std::filesystem::path& file, const std::string& what, std::optional<long> frame) {
  return Error(ExitCode::bad_input, where(file, frame) + ": " + what);
}

Error io_error(const std::filesystem::path& file, const std::string& what) {
  return Error(ExitCode::io, where(file) + ": " + what);
}

Error bad_arguments(const std::string& what) { return Error(ExitCode::bad_arguments, what); }

Error internal_error(const std::string& what) { return Error(ExitCode::internal, "internal error: " + what); }

}  // namespace surfcap::core
