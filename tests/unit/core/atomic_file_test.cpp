#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <vector>

#include "surfcap/core/atomic_file.hpp"
#include "surfcap/core/error.hpp"
#include "test_support.hpp"

namespace surfcap {
namespace {

using testing::TemporaryDirectory;

TEST(AtomicFile, CommitRenamesOntoTarget) {
  TemporaryDirectory dir("atomic_commit");
  core::write_file_atomically(dir / "sub" / "out.txt", std::string_view("hello"));
  EXPECT_EQ(core::read_file(dir / "sub" / "out.txt"), "hello");
  EXPECT_EQ(testing::count_hidden_files(dir / "sub"), 0);
}

TEST(AtomicFile, AbandonedWriteLeavesNothingAndKeepsOldFile) {
  TemporaryDirectory dir("atomic_abandon");
  core::write_file_atomically(dir / "out.txt", std::string_view("previous"));
  {
    core::AtomicFile file(dir / "out.txt");
    file.write("partial new content");
    EXPECT_TRUE(std::filesystem::exists(file.temporary()));
    // no commit: an exception or a crash in the middle
  }
  EXPECT_EQ(core::read_file(dir / "out.txt"), "previous");
  EXPECT_EQ(testing::count_hidden_files(dir.path()), 0);
}

TEST(AtomicFile, ExceptionDuringWriteLeavesNoFile) {
  TemporaryDirectory dir("atomic_throw");
  EXPECT_THROW(
      {
        core::AtomicFile file(dir / "never.bin");
        file.write("abc");
        throw std::runtime_error("computation failed");
      },
      std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir / "never.bin"));
  EXPECT_EQ(testing::count_hidden_files(dir.path()), 0);
}

TEST(AtomicFile, UnwritableDirectoryIsIoError) {
  if (::geteuid() == 0) {
    // root ignores permissions: use a path under a regular file instead.
    TemporaryDirectory dir("atomic_unwritable");
    core::write_file_atomically(dir / "file", std::string_view("x"));
    try {
      core::write_file_atomically(dir / "file" / "child.txt", std::string_view("y"));
      FAIL();
    } catch (const core::Error& e) {
      EXPECT_EQ(e.code(), core::ExitCode::io);
      EXPECT_NE(std::string(e.what()).find("child.txt"), std::string::npos);
    }
    return;
  }
  EXPECT_THROW(core::write_file_atomically("/proc/surfcap-cannot-write", std::string_view("x")), core::Error);
}

TEST(AtomicFile, FileSizeLimitGivesIoErrorAndNoFile) {
  // A full disk, simulated with RLIMIT_FSIZE in a child process.
  TemporaryDirectory dir("atomic_full");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    int code = 10;
    try {
      const std::string big(1 << 20, 'x');
      core::write_file_atomically(dir / "big.bin", big);
    } catch (const core::Error& e) {
      code = e.exit_code();
    }
    ::_exit(code);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), static_cast<int>(core::ExitCode::io));
  EXPECT_FALSE(std::filesystem::exists(dir / "big.bin"));
  EXPECT_EQ(testing::count_hidden_files(dir.path()), 0);
}

/// Forks a child that opens an AtomicFile on `target`, writes, and then (ready written to `ready`)
/// waits for a byte on `go` before committing — or, with go < 0, kills itself (a SIGKILLed run).
pid_t child_writing(const std::filesystem::path& target, int ready, int go) {
  const pid_t child = ::fork();
  if (child != 0) return child;
  core::AtomicFile file(target);
  file.write("complete");
  char byte = 1;
  if (::write(ready, &byte, 1) != 1) ::_exit(20);
  if (go < 0) ::raise(SIGKILL);
  if (::read(go, &byte, 1) != 1) ::_exit(21);
  file.commit();
  ::_exit(0);
}

std::vector<std::filesystem::path> hidden_files(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().filename().string()[0] == '.') files.push_back(entry.path());
  return files;
}

TEST(AtomicFile, NextWriterRemovesWhatKilledRunsLeftButNotLiveWriters) {
  TemporaryDirectory dir("atomic_stale");
  int ready[2], go[2];
  ASSERT_EQ(::pipe(ready), 0);
  ASSERT_EQ(::pipe(go), 0);
  char byte = 1;
  // A live writer of live.bin (started first: its own clean-up sees an empty directory) ...
  const pid_t live = child_writing(dir / "live.bin", ready[1], go[0]);
  struct Reaper {  // never leave the live child blocked, whatever fails below
    pid_t pid;
    ~Reaper() {
      if (pid > 0 && ::kill(pid, SIGKILL) == 0) ::waitpid(pid, nullptr, 0);
    }
  } reaper{live};
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  // ... a run killed in the middle of writing killed.bin ...
  const pid_t killed = child_writing(dir / "killed.bin", ready[1], -1);
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  int status = 0;
  ::waitpid(killed, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  std::vector<std::filesystem::path> stale;
  for (const auto& file : hidden_files(dir.path()))
    if (file.filename().string().starts_with(".killed.bin.tmp-")) stale.push_back(file);
  ASSERT_EQ(stale.size(), 1u);
  // ... and a dead process's temporary written from another host (a shared disk).
  const auto other_host = dir / (".x.bin.tmp-another-host-" + std::to_string(killed) + "-0");
  std::filesystem::copy_file(stale[0], other_host);
  // All of them last written before this process started (a previous run).
  const auto before = std::filesystem::file_time_type::clock::now() - std::chrono::hours(1);
  for (const auto& file : hidden_files(dir.path())) std::filesystem::last_write_time(file, before);
  EXPECT_EQ(hidden_files(dir.path()).size(), 3u);

  core::write_file_atomically(dir / "next.bin", std::string_view("next"));
  EXPECT_FALSE(std::filesystem::exists(stale[0])) << "the killed run's temporary was kept";
  EXPECT_TRUE(std::filesystem::exists(other_host)) << "another host's temporary was removed";
  EXPECT_EQ(hidden_files(dir.path()).size(), 2u);
  // The live writer still completes.
  ASSERT_EQ(::write(go[1], &byte, 1), 1);
  ::waitpid(live, &status, 0);
  reaper.pid = -1;
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(core::read_file(dir / "live.bin"), "complete");
  EXPECT_FALSE(std::filesystem::exists(dir / "killed.bin"));
  for (const int fd : {ready[0], ready[1], go[0], go[1]}) ::close(fd);
}

}  // namespace
}  // namespace surfcap
