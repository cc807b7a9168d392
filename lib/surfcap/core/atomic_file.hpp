#pragma once
// Outputs are written to a hidden temporary name beside the target and renamed when complete,
// so a killed or failed job never leaves a file that looks finished. What a killed job left is
// removed by the next process writing into that directory (docs/reliability.md).

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace surfcap::core {

class AtomicFile {
 public:
  /// Opens "<dir>/.<name>.tmp-<host>-<pid>-<n>"; creates the parent directories. The first time
  /// this process writes into <dir>, it removes the temporaries there of dead processes of this
  /// host last written before it started (killed runs). Throws io_error (exit 4).
  explicit AtomicFile(std::filesystem::path target);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  /// Removes the temporary file if commit() was not reached.
  ~AtomicFile();

  void write(const void* data, std::size_t size);
  void write(std::string_view text) { write(text.data(), text.size()); }
  /// Flushes, fsyncs and renames onto the target. Throws io_error on failure (full disk...).
  void commit();

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& temporary() const { return temporary_; }

 private:
  [[noreturn]] void fail(const char* step, int error_number);

  std::filesystem::path target_;
  std::filesystem::path temporary_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

/// Writes `bytes` to `target` atomically.
void write_file_atomically(const std::filesystem::path& target, std::span<const std::byte> bytes);
void write_file_atomically(const std::filesystem::path& target, std::string_view text);

/// Reads a whole file; io_error if it cannot.
std::string read_file(const std::filesystem::path& path);

}  // namespace surfcap::core
