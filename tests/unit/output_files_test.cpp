// core/output_files.h: a run's outputs, checked first and committed together.
#include "core/output_files.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/error.h"

namespace pvrt {
namespace {

namespace fs = std::filesystem;

// A fresh folder of the test's own.
struct Folder {
  fs::path dir;
  explicit Folder(const std::string& name) {
    dir = fs::temp_directory_path() / ("pvrt_output_files_" + name + "_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Folder() { fs::remove_all(dir); }
  std::string operator/(const std::string& f) const { return (dir / f).string(); }
  std::vector<std::string> names() const {
    std::vector<std::string> n;
    for (const auto& e : fs::directory_iterator(dir)) n.push_back(e.path().filename().string());
    std::sort(n.begin(), n.end());
    return n;
  }
};

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// The message of the pvrt::Error that `f` throws, or "" when it throws none.
template <class F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::OutputError) << e.what();
    return e.what();
  }
  return "";
}

TEST(OutputFiles, NothingIsCommittedUntilTheEnd) {
  Folder d("commit");
  write(d / "a.txt", "old a");
  {
    OutputFiles out;
    out.output(d / "a.txt", "-o");
    out.output(d / "b.txt", "--save-scene");
    out.stageBytes(d / "a.txt", "new a");
    out.stageBytes(d / "b.txt", "new b");
    EXPECT_EQ(read(d / "a.txt"), "old a");
    EXPECT_FALSE(fs::exists(d / "b.txt"));
    // Dropped without commit: the temporaries go, the old file stays.
  }
  EXPECT_EQ(d.names(), std::vector<std::string>{"a.txt"});
  EXPECT_EQ(read(d / "a.txt"), "old a");
  OutputFiles out;
  out.output(d / "a.txt", "-o");
  out.output(d / "b.txt", "--save-scene");
  out.stageBytes(d / "a.txt", "new a");
  out.stageBytes(d / "b.txt", "new b");
  out.commit();
  EXPECT_EQ(read(d / "a.txt"), "new a");
  EXPECT_EQ(read(d / "b.txt"), "new b");
  EXPECT_EQ(d.names(), (std::vector<std::string>{"a.txt", "b.txt"}));
}

// The reported attack: a link planted at the predictable name of older pvrt.
TEST(OutputFiles, PlantedLinksAreNeverFollowed) {
  Folder d("planted");
  write(d / "victim", "victim");
  for (int n = 0; n < 4; ++n)
    fs::create_symlink(d / "victim", d / (".out.tmp-" + std::to_string(getpid()) + "-" + std::to_string(n) + ".png"));
  OutputFiles out;
  out.output(d / "out.png", "-o");
  std::set<std::string> names;
  for (int i = 0; i < 200; ++i) {  // unpredictable: 200 stagings, 200 names, none with the pid
    const std::string tmp = out.stage(d / "out.png");
    names.insert(tmp);
    // Not made from the pid as the planted names are (its digits alone may turn up in the 16
    // random hex digits by chance: 4% of runs for a 4-digit pid).
    EXPECT_EQ(fs::path(tmp).filename().string().find("-" + std::to_string(getpid()) + "-"), std::string::npos) << tmp;
    struct stat st {};
    ASSERT_EQ(::lstat(tmp.c_str(), &st), 0);
    EXPECT_TRUE(S_ISREG(st.st_mode));
  }
  EXPECT_EQ(names.size(), 200u);
  out.stageBytes(d / "out.png", "image");
  out.commit();
  EXPECT_EQ(read(d / "victim"), "victim");
  EXPECT_EQ(read(d / "out.png"), "image");
}

TEST(OutputFiles, ReplacedTemporaryIsRefused) {
  Folder d("replaced");
  OutputFiles out;
  out.output(d / "out.txt", "-o");
  const std::string tmp = out.stage(d / "out.txt");
  fs::remove(tmp);
  fs::create_symlink(d / "elsewhere", tmp);
  EXPECT_NE(errorOf([&] { out.commit(); }).find("was replaced or removed"), std::string::npos);
  EXPECT_FALSE(fs::exists(d / "out.txt"));
}

TEST(OutputFiles, PathsAreCheckedWhenPlanned) {
  Folder d("checks");
  write(d / "scene.xml", "<scene/>");
  fs::create_directory(d / "sub");
  OutputFiles out;
  out.input(d / "scene.xml");
  EXPECT_NE(errorOf([&] { out.output(d / "scene.xml", "-o"); }).find("it is an input of this run"), std::string::npos);
  EXPECT_NE(errorOf([&] { out.output(d / "nope/x.png", "-o"); }).find("no such directory"), std::string::npos);
  EXPECT_NE(errorOf([&] { out.output(d / "scene.xml/x.png", "-o"); }).find("is not a directory"), std::string::npos);
  EXPECT_NE(errorOf([&] { out.output(d / "sub", "-o"); }).find("it is a directory"), std::string::npos);
  out.output(d / "x.png", "-o");
  EXPECT_NE(errorOf([&] { out.output(d / "sub/../x.png", "--load-map"); }).find("also the output of -o"),
            std::string::npos);
  // A link to an input is the input; a hard link to an output is the output.
  fs::create_symlink(d / "scene.xml", d / "link.xml");
  EXPECT_NE(errorOf([&] { out.output(d / "link.xml", "--save-scene"); }).find("input"), std::string::npos);
  write(d / "y.png", "y");
  out.output(d / "y.png", "--plot");
  fs::create_hard_link(d / "y.png", d / "hard.png");
  EXPECT_NE(errorOf([&] { out.output(d / "hard.png", "--csv"); }).find("also the output of --plot"), std::string::npos);
}

TEST(OutputFiles, ThroughALinkTheTargetIsReplaced) {
  Folder d("link");
  fs::create_directory(d / "real");
  write(d / "real/t.txt", "old");
  fs::create_symlink("real/t.txt", d / "l1");
  fs::create_symlink("l1", d / "l2");  // a chain, relative links
  OutputFiles out;
  out.output(d / "l2", "-o");
  out.stageBytes(d / "l2", "new");
  out.commit();
  EXPECT_TRUE(fs::is_symlink(d / "l2"));
  EXPECT_TRUE(fs::is_symlink(d / "l1"));
  EXPECT_EQ(read(d / "real/t.txt"), "new");
}

TEST(OutputFiles, PermissionsAreKept) {
  Folder d("mode");
  write(d / "f.txt", "old");
  fs::permissions(d / "f.txt", fs::perms(0640));
  OutputFiles out;
  out.output(d / "f.txt", "-o");
  out.stageBytes(d / "f.txt", "new");
  out.commit();
  EXPECT_EQ(int(fs::status(d / "f.txt").permissions() & fs::perms::mask), 0640);
}

}  // namespace
}  // namespace pvrt
