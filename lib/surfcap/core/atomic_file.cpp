#include "surfcap/core/atomic_file.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <string>

#include "surfcap/core/error.hpp"
#include "surfcap/core/input_policy.hpp"

namespace surfcap::core {
namespace {

// Temporaries written before this process started (by static initialisation) can only be another
// run's.
const std::filesystem::file_time_type process_start = std::filesystem::file_time_type::clock::now();

/// This host's name as it goes into temporary names: at most 32 characters, no '/'.
const std::string& host_tag() {
  static const std::string tag = [] {
    char name[256] = {};
    std::string host = ::gethostname(name, sizeof name - 1) == 0 && name[0] ? name : "localhost";
    host.resize(std::min<std::size_t>(host.size(), 32));
    std::replace(host.begin(), host.end(), '/', '_');
    return host;
  }();
  return tag;
}

std::filesystem::path temporary_name(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  const std::string name = "." + target.filename().string() + ".tmp-" + host_tag() + "-" +
                           std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
  return target.parent_path() / name;
}

bool all_digits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); });
}

/// The pid of a temporary "." NAME ".tmp-" HOST "-" PID "-" N written on this host, else -1.
long temporary_pid(const std::string& file) {
  const std::size_t tag = file.rfind(".tmp-");
  if (file.empty() || file[0] != '.' || tag == std::string::npos || tag == 0) return -1;
  const std::string_view rest = std::string_view(file).substr(tag + 5);
  const std::size_t last = rest.rfind('-');
  if (last == std::string_view::npos || last == 0) return -1;
  const std::size_t second = rest.rfind('-', last - 1);
  if (second == std::string_view::npos) return -1;
  const std::string_view pid = rest.substr(second + 1, last - second - 1);
  if (rest.substr(0, second) != host_tag() || !all_digits(pid) || pid.size() > 9 || !all_digits(rest.substr(last + 1)))
    return -1;
  return std::stol(std::string(pid));
}

/// Removes, once per directory and process, the temporaries that killed runs on this host left in
/// `directory`: their process is gone and they were last written before this process started. A
/// live writer's (even another job's) or another host's temporary is never touched.
void remove_stale_temporaries(const std::filesystem::path& directory) {
  static std::mutex mutex;
  static std::set<std::filesystem::path> cleaned;
  {
    const std::lock_guard lock(mutex);
    if (!cleaned.insert(directory).second) return;
  }
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator(directory, ec); !ec && it != std::filesystem::directory_iterator();
       it.increment(ec)) {
    const long pid = temporary_pid(it->path().filename().string());
    if (pid <= 0 || pid == ::getpid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive (EPERM: someone else's)
    std::error_code file_ec;
    const auto written = std::filesystem::last_write_time(it->path(), file_ec);
    if (!file_ec && written < process_start) std::filesystem::remove(it->path(), file_ec);
  }
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  if (target_.filename().empty()) throw io_error(target_, "not a file name");
  std::error_code ec;
  if (target_.has_parent_path()) {
    std::filesystem::create_directories(target_.parent_path(), ec);
    if (ec) throw io_error(target_, "cannot create the directory: " + ec.message());
  }
  remove_stale_temporaries(target_.has_parent_path() ? target_.parent_path() : std::filesystem::path("."));
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
  // Never block on a FIFO nor read a device for ever; a file is held whole in memory.
  check_memory(path, "reading the whole file", static_cast<double>(check_regular_file(path)));
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
