#include "surfcap/core/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "surfcap/core/error.hpp"

namespace surfcap::core {
namespace {

std::filesystem::path temporary_name(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  const std::string name = "." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                           std::to_string(counter.fetch_add(1));
  return target.parent_path() / name;
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  if (target_.filename().empty()) throw io_error(target_, "not a file name");
  std::error_code ec;
  if (target_.has_parent_path()) {
    std::filesystem::create_directories(target_.parent_path(), ec);
    if (ec) throw io_error(target_, "cannot create the directory: " + ec.message());
  }
  temporary_ = temporary_name(target_);
  file_ = std::fopen(temporary_.c_str(), "wb");
  if (!file_) throw io_error(target_, std::string("cannot open for writing: ") + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_) {
    std::error_code ec;
    std::filesystem::remove(temporary_, ec);
  }
}

void AtomicFile::fail(const char* step, int error_number) {
  if (file_) std::fclose(file_);
  file_ = nullptr;
  std::error_code ec;
  std::filesystem::remove(temporary_, ec);
  throw io_error(target_, std::string(step) + " failed: " + std::strerror(error_number));
}

void AtomicFile::write(const void* data, std::size_t size) {
  if (!file_) throw internal_error("write to a closed AtomicFile " + target_.string());
  if (size == 0) return;
  if (std::fwrite(data, 1, size, file_) != size) fail("write", errno);
}

void AtomicFile::commit() {
  if (!file_) throw internal_error("commit of a closed AtomicFile " + target_.string());
  if (std::fflush(file_) != 0) fail("write", errno);
  if (::fsync(::fileno(file_)) != 0 && errno != EINVAL) fail("fsync", errno);
  const int closed = std::fclose(file_);
  file_ = nullptr;
  if (closed != 0) fail("close", errno);
  if (std::rename(temporary_.c_str(), target_.c_str()) != 0) fail("rename", errno);
  committed_ = true;
}

void write_file_atomically(const std::filesystem::path& target, std::span<const std::byte> bytes) {
  AtomicFile file(target);
  file.write(bytes.data(), bytes.size());
  file.commit();
}

void write_file_atomically(const std::filesystem::path& target, std::string_view text) {
  AtomicFile file(target);
  file.write(text);
  file.commit();
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int error_number = errno;
    if (!std::filesystem::exists(path)) throw io_error(path, "no such file");
    throw io_error(path, std::string("cannot open: ") + std::strerror(error_number));
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw io_error(path, "read failed");
  return std::move(buffer).str();
}

}  // namespace surfcap::core
