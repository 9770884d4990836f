#include "common/output_file.hpp"

#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.hpp"

namespace rpu {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class OutputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("output_file_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static void write(const fs::path& file, const std::string& text) { std::ofstream(file, std::ios::binary) << text; }
  static std::string read(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  // Every file in `dir` but the target: leftover temporaries.
  static std::vector<std::string> others(const fs::path& dir, const fs::path& target) {
    std::vector<std::string> names;
    for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
      if (e.path().filename() != target.filename()) names.push_back(e.path().filename().string());
    }
    return names;
  }
  // The message of the rpu::Error `f` throws.
  template <class F>
  static std::string error_of(F&& f) {
    try {
      f();
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  }

  fs::path dir_;
};

TEST_F(OutputFileTest, CommitReplacesTheTargetAndLeavesNoTemporary) {
  const fs::path target = dir_ / "out.json";
  write(target, "old");
  ::chmod(target.c_str(), 0640);
  OutputFile out(target);
  EXPECT_EQ(out.temp_path().parent_path(), dir_);
  EXPECT_EQ(out.temp_path().extension(), ".json");
  EXPECT_EQ(out.temp_path().filename().string().front(), '.');
  out.stream() << "new contents";
  EXPECT_EQ(read(target), "old");  // nothing reaches the target before commit()
  out.commit();
  EXPECT_EQ(read(target), "new contents");
  EXPECT_EQ(others(dir_, target), std::vector<std::string>{});
  struct stat st {};
  ASSERT_EQ(::stat(target.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);  // a replaced file keeps its permissions
}

TEST_F(OutputFileTest, DestroyedWithoutCommitKeepsTheOldFile) {
  const fs::path target = dir_ / "out.csv";
  write(target, "old");
  {
    OutputFile out(target);
    out.stream() << std::string(200000, 'x');  // more than the buffer: on disk already
  }
  EXPECT_EQ(read(target), "old");
  EXPECT_EQ(others(dir_, target), std::vector<std::string>{});
}

TEST_F(OutputFileTest, FileSizeLimitFailsTheCommitAndKeepsTheOldFile) {
  const fs::path target = dir_ / "big.json";
  write(target, "old");
  OutputFile out(target);  // ignores SIGXFSZ: the write returns EFBIG
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  rlimit small = saved;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  out.stream() << std::string(1 << 20, 'x');
  const std::string message = error_of([&] { out.commit(); });
  ::setrlimit(RLIMIT_FSIZE, &saved);
  EXPECT_EQ(message, target.string() + ": cannot write the file: File too large; the previous file is unchanged");
  EXPECT_EQ(read(target), "old");
  EXPECT_EQ(others(dir_, target), std::vector<std::string>{});
}

TEST_F(OutputFileTest, FullDiskFailsTheCommitAndKeepsTheOldFile) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a 64 KiB tmpfs (the RLIMIT_FSIZE test always runs)";
  const fs::path mnt = dir_ / "tmpfs";
  fs::create_directories(mnt);
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=64k") != 0) {
    GTEST_SKIP() << "mount -t tmpfs failed: " << std::strerror(errno);
  }
  const fs::path target = mnt / "full.csv";
  write(target, "old");
  std::string message;
  {
    OutputFile out(target);
    out.stream() << std::string(1 << 20, 'x');
    message = error_of([&] { out.commit(); });
  }
  const std::string old = read(target);
  const std::vector<std::string> left = others(mnt, target);
  ::umount(mnt.c_str());
  EXPECT_EQ(message,
            target.string() + ": cannot write the file: No space left on device; the previous file is unchanged");
  EXPECT_EQ(old, "old");
  EXPECT_EQ(left, std::vector<std::string>{});
}

TEST_F(OutputFileTest, SigintRemovesTheTemporaryAndKeepsTheOldFile) {
  const fs::path target = dir_ / "trace.json";
  write(target, "old");
  EXPECT_EXIT(
      {
        OutputFile out(target);
        out.stream() << std::string(200000, 'x');
        ::raise(SIGINT);
      },
      ::testing::KilledBySignal(SIGINT), "");
  EXPECT_EQ(read(target), "old");
  EXPECT_EQ(others(dir_, target), std::vector<std::string>{});
}

TEST_F(OutputFileTest, LibraryWritingTheTemporaryByName) {
  const fs::path target = dir_ / "waves.fst";
  {
    OutputFile out(target);
    // As the FST writer does: remove the file and create it again.
    fs::remove(out.temp_path());
    std::ofstream(out.temp_path(), std::ios::binary) << "waves";
    out.commit();
  }
  EXPECT_EQ(read(target), "waves");
  OutputFile nothing(target);
  EXPECT_EQ(error_of([&] { nothing.commit(); }),
            target.string() + ": cannot write the file: nothing was written to it; the previous file is unchanged");
  EXPECT_EQ(read(target), "waves");
}

TEST_F(OutputFileTest, CallersCheckThatFailsKeepsTheOldFile) {
  const fs::path target = dir_ / "image.png";
  write(target, "old");
  OutputFile out(target);
  std::ofstream(out.temp_path(), std::ios::binary) << "truncated";
  EXPECT_EQ(error_of([&] { out.fail("it reads back as 3x2 pixels, expected 4x4"); }),
            target.string() +
                ": cannot write the file: it reads back as 3x2 pixels, expected 4x4; the previous file is unchanged");
  EXPECT_EQ(read(target), "old");
  EXPECT_EQ(others(dir_, target), std::vector<std::string>{});
}

TEST_F(OutputFileTest, BadPathsAreNamedBeforeAnythingIsWritten) {
  const fs::path missing = dir_ / "no_such_dir" / "out.png";
  EXPECT_EQ(error_of([&] { check_output_path(missing); }),
            missing.string() + ": the directory '" + (dir_ / "no_such_dir").string() +
                "' does not exist; create it or choose another path");
  EXPECT_EQ(error_of([&] { OutputFile out(missing); }), error_of([&] { check_output_path(missing); }));
  EXPECT_EQ(error_of([&] { check_output_path(dir_); }),
            dir_.string() + ": is a directory; give the output a file name");
  EXPECT_EQ(error_of([] { check_output_path("/dev/null"); }),
            "/dev/null: not a regular file; outputs are written beside the target and renamed over it, so give the "
            "path of a file");
  const fs::path locked = dir_ / "locked";
  fs::create_directories(locked);
  ::chmod(locked.c_str(), 0500);
  // Root may write anywhere: only a read-only file system stops it.
  if (::geteuid() != 0) {
    EXPECT_EQ(error_of([&] { check_output_path(locked / "x.png"); }),
              (locked / "x.png").string() + ": cannot create files in '" + locked.string() + "': Permission denied");
  }
  EXPECT_EQ(others(dir_, "locked"), std::vector<std::string>{});
}

}  // namespace
}  // namespace rpu
