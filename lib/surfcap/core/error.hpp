#pragma once
// The one error type of surfcap: thrown where input is wrong, caught once in each tool's main.

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

namespace surfcap::core {

/// Process exit codes, documented in docs/cli.md.
enum class ExitCode : int {
  ok = 0,
  internal = 1,       ///< a bug or an unexpected failure
  bad_arguments = 2,  ///< the command line or a config file is wrong
  bad_input = 3,      ///< an input file exists but its content is wrong
  io = 4,             ///< a file could not be opened, read or written (missing, permissions, full disk)
};

class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ExitCode code() const noexcept { return code_; }
  int exit_code() const noexcept { return static_cast<int>(code_); }

 private:
  ExitCode code_;
};

/// "'path' (frame 12)": how every message names where a problem is.
std::string where(const std::filesystem::path& file, std::optional<long> frame = std::nullopt);

/// Content of `file` is wrong (exit code 3); the message names the file and frame.
Error bad_input(const std::filesystem::path& file, const std::string& what,
                std::optional<long> frame = std::nullopt);
/// `file` could not be read or written (exit code 4); `what` says why (strerror etc.).
Error io_error(const std::filesystem::path& file, const std::string& what);
/// Command line or config is wrong (exit code 2).
Error bad_arguments(const std::string& what);
/// Something that should not happen (exit code 1).
Error internal_error(const std::string& what);

}  // namespace surfcap::core
