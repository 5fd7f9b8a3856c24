// A mapped scene file: the bytes as read, pages dropped and read again, and a file that
// shrinks under its mapping read as zeros instead of killing the process with SIGBUS.
#include "core/mapped_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "scene/xml_document.h"

namespace pvrt {
namespace {

namespace fs = std::filesystem;

class MappedFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (fs::temp_directory_path() / ("pvrt_mapped_" + std::to_string(::getpid()) + ".txt")).string();
  }
  void TearDown() override { fs::remove(path_); }
  // A file of `n` bytes, each one its offset's low byte but never 0.
  std::string write(size_t n) {
    std::string s(n, ' ');
    for (size_t i = 0; i < n; ++i) s[i] = char('a' + i % 26);
    std::ofstream(path_, std::ios::binary) << s;
    return s;
  }
  int open() const { return ::open(path_.c_str(), O_RDONLY | O_CLOEXEC); }
  std::string path_;
};

size_t page() { return size_t(::sysconf(_SC_PAGESIZE)); }

TEST_F(MappedFileTest, HoldsTheFileAsWritten) {
  const std::string s = write(3 * page() + 17);
  const int fd = open();
  const MappedFile m(fd, s.size());
  ::close(fd);  // the mapping outlives the descriptor
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m.bytes(), s);
  EXPECT_FALSE(m.shrunk());
}

TEST_F(MappedFileTest, DroppedPagesAreReadAgain) {
  const std::string s = write(8 * page());
  const int fd = open();
  const MappedFile m(fd, s.size());
  ::close(fd);
  ASSERT_TRUE(m.ok());
  EXPECT_TRUE(m.drop(page() / 2, 5 * page()));  // pages 1-4 whole
  EXPECT_FALSE(m.drop(10, 20));                 // within one page: nothing whole to drop
  EXPECT_EQ(m.bytes(), s);
}

TEST_F(MappedFileTest, AFileThatShrinksReadsAsZerosAndSaysSo) {
  const std::string s = write(6 * page());
  const int fd = open();
  const MappedFile m(fd, s.size());
  ::close(fd);
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m.bytes()[0], 'a');
  ::truncate(path_.c_str(), off_t(page()));
  // Past the file's new end: without the guard, this read is a SIGBUS.
  const volatile char* p = m.bytes().data();
  EXPECT_EQ(p[3 * page() + 5], 0);
  EXPECT_TRUE(m.shrunk());
  EXPECT_EQ(p[10], s[10]);  // the page still in the file is as it was
}

TEST_F(MappedFileTest, TheActionBeforeIsBackOnceNoFileIsMapped) {
  const std::string s = write(2 * page());
  struct sigaction before {}, after {};
  ::sigaction(SIGBUS, nullptr, &before);
  {
    const int fd = open();
    const MappedFile m(fd, s.size());
    ::close(fd);
    ASSERT_TRUE(m.ok());
  }
  ::sigaction(SIGBUS, nullptr, &after);
  EXPECT_EQ(after.sa_handler, before.sa_handler);
  EXPECT_EQ(after.sa_flags & SA_SIGINFO, before.sa_flags & SA_SIGINFO);
}

TEST_F(MappedFileTest, ASigbusThatIsNotAFaultAtAMappedFileStillEndsTheProcess) {
  const std::string s = write(2 * page());
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::signal(SIGBUS, SIG_DFL);
    const int fd = open();
    const MappedFile m(fd, s.size());
    ::raise(SIGBUS);  // sent, not a fault: the default action, as without a mapping
    ::_exit(m.ok() ? 3 : 4);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status)) << "exit status " << WEXITSTATUS(status);
  EXPECT_EQ(WTERMSIG(status), SIGBUS);
}

TEST_F(MappedFileTest, SceneBytesOfABigFileSayWhenItChangedSize) {
  const std::string s = write(33u << 20);  // big enough to be mapped
  {
    const SceneBytes bytes(path_);
    EXPECT_EQ(bytes.view(), s);
    EXPECT_TRUE(bytes.intact());
    std::ofstream(path_, std::ios::app) << "x";
    EXPECT_FALSE(bytes.intact());  // grew: the view misses the end
  }
  write(33u << 20);
  const SceneBytes bytes(path_);
  ::truncate(path_.c_str(), off_t(1) << 20);
  const volatile char* p = bytes.view().data();
  EXPECT_EQ(p[20u << 20], 0);
  EXPECT_FALSE(bytes.intact());
  const SceneBytes read(path_, SceneBytes::Way::Read);
  EXPECT_EQ(read.view().size(), size_t(1) << 20);
}

}  // namespace
}  // namespace pvrt
