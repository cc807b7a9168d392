#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

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

}  // namespace
}  // namespace surfcap
