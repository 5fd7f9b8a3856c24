// <include file="..."/> in the XML loader: paths relative to the including file, the included
// elements in place, errors naming the included file and line, cycles and depth refused.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "core/error.h"
#include "core/interrupt.h"
#include "scene/xml_loader.h"

namespace pvrt {
namespace {

namespace fs = std::filesystem;

// A fresh folder of scene files for one test.
class Files {
 public:
  explicit Files(const std::string& name) : dir_(fs::path(PVRT_BINARY_DIR) / "xml-include-test" / name) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  std::string write(const std::string& relative, const std::string& text) const {
    const fs::path p = dir_ / relative;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p.string();
  }
  std::string path(const std::string& relative) const { return (dir_ / relative).string(); }

 private:
  fs::path dir_;
};

std::string errorOf(const std::string& path) {
  try {
    loadSceneFile(path);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::SceneError);
    return e.what();
  }
  return "(loaded)";
}

TEST(XmlInclude, NestedFilesAreReadInPlaceRelativeToTheIncludingFile) {
  Files f("nested");
  f.write("parts/lights.xml", R"(<scene>
  <light_source location="0 5 0"/>
  <include file="../materials/glass.xml"/>
</scene>)");
  f.write("materials/glass.xml", R"(<scene><material name="glass"><interior ior="1.5"/></material></scene>)");
  const std::string main = f.write("main.xml", R"(<scene>
  <sphere center="0 0 0" radius="1"/>
  <include file="parts/lights.xml"/>
  <sphere center="0 0 3" radius="2" material="glass"/>
</scene>)");
  const SceneDesc s = loadSceneFile(main);
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.lights.size(), 1u);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.objects[1].namedMaterial, 0);
  EXPECT_EQ(s.path, main);
  // Each element keeps its own file and line.
  EXPECT_EQ(s.lights[0].loc.file.str(), f.path("parts/lights.xml"));
  EXPECT_EQ(s.lights[0].loc.line, 2);
  EXPECT_EQ(s.materials[0].loc.file.str(), f.path("materials/glass.xml"));
  EXPECT_EQ(s.objects[1].loc.file.str(), main);
  EXPECT_EQ(s.objects[1].loc.line, 4);
}

TEST(XmlInclude, ErrorsNameTheIncludedFileAndLine) {
  Files f("error");
  f.write("sub/bad.xml", "<scene>\n\n  <sphere center=\"0 0 0\" radus=\"1\"/>\n</scene>");
  const std::string main = f.write("main.xml", "<scene>\n  <include file=\"sub/bad.xml\"/>\n</scene>");
  EXPECT_EQ(errorOf(main),
            f.path("sub/bad.xml") + ":3: error: sphere: unknown attribute 'radus' (did you mean 'radius'?)");
}

TEST(XmlInclude, WhatDependsOnEarlierElementsSpansFiles) {
  Files f("order");
  f.write("camera.xml", "<scene>\n  <camera location=\"0 0 -5\"/>\n</scene>");
  f.write("material.xml", "<scene>\n  <material name=\"m\"/>\n</scene>");
  const std::string twice = f.write("twice.xml", "<scene>\n  <camera/>\n  <include file=\"camera.xml\"/>\n</scene>");
  EXPECT_EQ(errorOf(twice), f.path("camera.xml") + ":2: error: camera: may appear only once");
  const std::string redefined =
      f.write("redefined.xml", "<scene>\n  <include file=\"material.xml\"/>\n  <material name=\"m\"/>\n</scene>");
  EXPECT_EQ(errorOf(redefined), f.path("redefined.xml") + ":3: error: material: material 'm' is already defined at " +
                                    f.path("material.xml") + ":2");
}

TEST(XmlInclude, CyclesAreRefusedWithTheirChain) {
  Files f("cycle");
  const std::string a = f.write("a.xml", "<scene>\n  <include file=\"sub/b.xml\"/>\n</scene>");
  f.write("sub/b.xml", "<scene>\n\n  <include file=\"../a.xml\"/>\n</scene>");
  EXPECT_EQ(errorOf(a), f.path("sub/b.xml") + ":3: error: include: \"../a.xml\" makes a cycle: " + a + " -> " +
                            f.path("sub/b.xml") + " -> " + a);
  const std::string self = f.write("self.xml", "<scene><include file=\"./self.xml\"/></scene>");
  EXPECT_NE(errorOf(self).find("self.xml:1: error: include: \"./self.xml\" makes a cycle"), std::string::npos);
}

TEST(XmlInclude, DepthIsLimited) {
  Files f("deep");
  for (int i = 0; i < 20; ++i)
    f.write("d" + std::to_string(i) + ".xml", "<scene><include file=\"d" + std::to_string(i + 1) + ".xml\"/></scene>");
  f.write("d20.xml", "<scene/>");
  EXPECT_NE(errorOf(f.path("d0.xml")).find("d16.xml:1: error: include: more than 16 nested includes"),
            std::string::npos);
  EXPECT_NO_THROW(loadSceneFile(f.path("d4.xml")));  // 16 deep: allowed
}

// Files that each include the next one `fanOut` times, `depth` deep: no cycle and within
// the depth limit, yet fanOut^depth reads of the last one. Returns the first file.
std::string includeFan(const Files& f, int fanOut, int depth) {
  for (int i = 0; i < depth; ++i) {
    std::string xml = "<scene>\n";
    for (int k = 0; k < fanOut; ++k) xml += "  <include file=\"f" + std::to_string(i + 1) + ".xml\"/>\n";
    f.write("f" + std::to_string(i) + ".xml", xml + "</scene>\n");
  }
  f.write("f" + std::to_string(depth) + ".xml", "<scene><light_source location=\"0 5 0\"/></scene>");
  return f.path("f0.xml");
}

// 4^8 = 65536 reads of f8.xml would take minutes (4^16, allowed by the depth, for ever).
TEST(XmlInclude, IncludesInAllAreLimited) {
  Files f("fan");
  const std::string message = errorOf(includeFan(f, 4, 8));
  EXPECT_NE(message.find(": error: include: more than 10000 files included in all"), std::string::npos) << message;
  EXPECT_EQ(loadSceneFile(includeFan(f, 2, 9)).lights.size(), 512u);  // 1022 includes: fine
}

// A signal while an included file is read ends the load as an interrupt (exit 130, the usual
// line), not as "cannot include" (exit 3). Where the signal lands is up to the clock; the
// outcome must be the same wherever it does.
TEST(XmlInclude, ASignalDuringIncludesIsAnInterrupt) {
  Files f("signal");
  const std::string top = includeFan(f, 3, 8);  // 9840 includes: a second or more
  std::thread signal([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    interrupt::set(SIGINT);
  });
  try {
    loadSceneFile(top);
    ADD_FAILURE() << "loaded in under 50 ms";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::Interrupted);
    EXPECT_STREQ(e.what(), "pvrt: interrupted; nothing was written");
  }
  signal.join();
  interrupt::clear();
}

TEST(XmlInclude, MissingFileAndBadAttributesAreErrorsAtTheInclude) {
  Files f("missing");
  const std::string main = f.write("main.xml", "<scene>\n  <include file=\"none.xml\"/>\n</scene>");
  // Why, once: not the path again and a second "error: cannot read scene:" (a 3000-level
  // path made a 6000-byte message).
  EXPECT_EQ(errorOf(main), main + ":2: error: include: cannot include \"none.xml\": No such file or directory");
  std::string deep;
  for (int i = 0; i < 3000; ++i) deep += "a/";
  const std::string longPath = f.write("long.xml", "<scene>\n  <include file=\"" + deep + "x.xml\"/>\n</scene>");
  EXPECT_LT(errorOf(longPath).size(), longPath.size() + 200);
  EXPECT_NE(errorOf(longPath).find("...\": "), std::string::npos);
  const std::string device = f.write("device.xml", "<scene>\n  <include file=\"/dev/null\"/>\n</scene>");
  EXPECT_EQ(errorOf(device), device + ":2: error: include: cannot include \"/dev/null\": not a regular file");
  const std::string noFile = f.write("nofile.xml", "<scene>\n  <include/>\n</scene>");
  EXPECT_NE(errorOf(noFile).find(noFile + ":2: error: include: "), std::string::npos);
  const std::string children =
      f.write("children.xml", "<scene>\n  <include file=\"x.xml\"><sphere/></include>\n</scene>");
  EXPECT_NE(errorOf(children).find("unexpected element inside <include>"), std::string::npos);
  const std::string notScene = f.write("notscene.xml", "<scene>\n  <include file=\"other.xml\"/>\n</scene>");
  f.write("other.xml", "<other/>");
  EXPECT_EQ(errorOf(notScene), f.path("other.xml") + ":1: error: other: the root element must be <scene>");
}

TEST(XmlInclude, ABigFileWithAnIncludeLoadsAsAWholeFileWould) {
  Files f("pieces");
  f.write("lights.xml", "<scene><light_source location=\"0 5 0\"/><sphere center=\"9 9 9\" radius=\"1\"/></scene>");
  std::string xml = "<scene>\n";
  for (int i = 0; i < 2000; ++i) xml += "  <sphere center=\"" + std::to_string(i) + " 0 0\" radius=\"0.5\"/>\n";
  xml += "  <include file=\"lights.xml\"/>\n";
  for (int i = 0; i < 2000; ++i) xml += "  <sphere center=\"0 " + std::to_string(i) + " 0\" radius=\"0.5\"/>\n";
  xml += "</scene>\n";
  const std::string big = f.write("big.xml", xml);
  LoadOptions pieces;
  pieces.pieceBytes = 4096;
  const SceneDesc whole = loadSceneFile(big), split = loadSceneFile(big, pieces);
  ASSERT_EQ(whole.objects.size(), 4001u);
  ASSERT_EQ(split.objects.size(), 4001u);
  EXPECT_EQ(split.objects[2000].loc.file.str(), f.path("lights.xml"));
  EXPECT_EQ(split.objects[2001].loc.line, whole.objects[2001].loc.line);
  EXPECT_EQ(split.lights.size(), 1u);
}

}  // namespace
}  // namespace pvrt
