// Loading a file in pieces (scene/xml_split.h): the cut finds the root's children or gives
// up, and a scene loaded in pieces equals the scene loaded whole, down to every line number
// and every error message.
#include "scene/xml_split.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "generate/random_scene.h"
#include "parallel/threads.h"
#include "scene/xml_loader.h"
#include "scene/xml_writer.h"

namespace pvrt {
namespace {

constexpr size_t kWhole = std::numeric_limits<size_t>::max();

std::string slice(const std::string& s, const XmlPiece& p) { return s.substr(p.begin, p.end - p.begin); }

// Each piece's first line is counted from the bytes before it, whatever runs of line feeds,
// long lines and blank lines lie there (the count goes 32 bytes at a time where it can).
TEST(XmlSplit, PiecesKnowTheirFirstLines) {
  std::mt19937 random(11);
  std::string xml = "<?xml version=\"1.0\"?>\n<scene>";
  for (int k = 0; k < 300; ++k) {
    xml += std::string(random() % 40, '\n') + std::string(random() % 70, ' ') + "<sphere center=\"0 0 0\"";
    xml += std::string(random() % 3, '\n') + " radius=\"" + std::to_string(1 + k) + "\"";
    xml += random() % 2 ? "/>" : ">\n  <pigment color=\"1 0 0\"/>\n</sphere>";
  }
  xml += "\n</scene>\n";
  for (size_t pieceBytes : {size_t(1), size_t(100), size_t(1000)}) {
    const std::optional<XmlSplit> split = splitXmlRoot(xml, pieceBytes);
    ASSERT_TRUE(split);
    for (const XmlPiece& p : split->pieces)
      ASSERT_EQ(p.firstLine, 1 + std::count(xml.begin(), xml.begin() + std::ptrdiff_t(p.begin), '\n'))
          << "piece at " << p.begin << ", pieces of " << pieceBytes << " bytes";
    EXPECT_EQ(split->bodyLines, std::count(xml.begin() + std::ptrdiff_t(split->bodyBegin),
                                           xml.begin() + std::ptrdiff_t(split->bodyEnd), '\n'));
  }
}

TEST(XmlSplit, CutsAfterWholeChildrenOfTheRoot) {
  const std::string xml =
      "<?xml version=\"1.0\"?>\n<!-- a > b -->\n<scene>\n"
      "  <sphere center=\"0 0 0\" radius=\"1\"><pigment color='1 0 0'/></sphere>\n"
      "  <!-- <sphere/> in a comment -->\n"
      "  <box corner1=\"0 0 0\" corner2=\"1 1 1\" material=\"a>b\"/>\n"
      "  <material name=\"m\">\n    <finish diffuse=\"0.5\"/>\n  </material>\n"
      "</scene>\n";
  const std::optional<XmlSplit> split = splitXmlRoot(xml, 1);
  ASSERT_TRUE(split);
  EXPECT_EQ(split->elements, 3u);
  EXPECT_EQ(xml.substr(0, split->bodyBegin), "<?xml version=\"1.0\"?>\n<!-- a > b -->\n<scene>");
  EXPECT_EQ(xml.substr(split->bodyEnd), "</scene>\n");
  ASSERT_EQ(split->pieces.size(), 3u);  // an element each, the last with the space before the end tag
  EXPECT_EQ(slice(xml, split->pieces[0]),
            "\n  <sphere center=\"0 0 0\" radius=\"1\"><pigment color='1 0 0'/></sphere>");
  EXPECT_EQ(slice(xml, split->pieces[1]),
            "\n  <!-- <sphere/> in a comment -->\n  <box corner1=\"0 0 0\" corner2=\"1 1 1\" material=\"a>b\"/>");
  EXPECT_EQ(slice(xml, split->pieces[2]), "\n  <material name=\"m\">\n    <finish diffuse=\"0.5\"/>\n  </material>\n");
  EXPECT_EQ(split->pieces[0].firstLine, 3);
  EXPECT_EQ(split->pieces[1].firstLine, 4);
  EXPECT_EQ(split->pieces[2].firstLine, 6);
  for (size_t i = 1; i < split->pieces.size(); ++i) EXPECT_EQ(split->pieces[i].begin, split->pieces[i - 1].end);

  // Big pieces: everything in one.
  const std::optional<XmlSplit> one = splitXmlRoot(xml, 1000);
  ASSERT_TRUE(one);
  ASSERT_EQ(one->pieces.size(), 1u);
  EXPECT_EQ(one->pieces[0].begin, one->bodyBegin);
  EXPECT_EQ(one->pieces[0].end, one->bodyEnd);
}

// The loader learns from the cut how many objects come before each piece.
TEST(XmlSplit, CountsTheChildrenItIsAskedAbout) {
  const std::string xml =
      "<scene>\n<sphere/><camera/>\n<box\ncorner1='0'/><mesh><sphere/></mesh>\n"
      "<!-- <sphere/> --><sphere>x</sphere><sphere2/></scene>";
  const auto isSphere = [](std::string_view name) { return name == "sphere" || name == "box"; };
  const std::optional<XmlSplit> split = splitXmlRoot(xml, 1, isSphere);
  ASSERT_TRUE(split);
  std::vector<size_t> counted;
  for (const XmlPiece& p : split->pieces) counted.push_back(p.counted);
  // Not the mesh, nor the sphere inside it, nor the one in a comment, nor the sphere2.
  EXPECT_EQ(counted, (std::vector<size_t>{1, 0, 1, 0, 1, 0}));
  EXPECT_EQ(splitXmlRoot(xml, 100, isSphere)->pieces.at(0).counted, 3u);
  EXPECT_EQ(splitXmlRoot(xml, 100)->pieces.at(0).counted, 0u);
}

TEST(XmlSplit, GivesUpOnWhatItDoesNotExpect) {
  for (const char* xml : {
           "<!DOCTYPE scene>\n<scene><sphere/></scene>",  // a DOCTYPE
           "<scene/>",                                    // nothing inside
           "<scene><sphere/>text</scene>",                // text among the children
           "<scene><?pi x?><sphere/></scene>",            // a processing instruction among them
           "<scene><![CDATA[x]]></scene>",                // CDATA among them
           "<scene><sphere><pigment></sphere>",           // no end tag for the root
           "<scene><sphere center=\"0 0 0></scene>",      // an unclosed quote
           "<scene><sphere><!ELEMENT x></sphere></scene>",
           "text<scene/>",
           "",
       })
    EXPECT_FALSE(splitXmlRoot(xml, 1)) << xml;
  std::string deep = "<scene>";
  for (int i = 0; i < 100; ++i) deep += "<a>";
  for (int i = 0; i < 100; ++i) deep += "</a>";
  EXPECT_FALSE(splitXmlRoot(deep + "</scene>", 1));
}

// Every line number the loader stores, in a fixed order.
std::vector<int> linesOf(const SceneDesc& s) {
  std::vector<int> lines{s.camera.loc.line, s.globals.loc.line, s.image ? s.image->loc.line : 0};
  auto material = [&](const MaterialDesc& m) {
    for (int line : {m.loc.line, m.pigment.loc.line}) lines.push_back(line);
  };
  for (const LightDesc& l : s.lights) lines.push_back(l.loc.line);
  for (const MaterialDesc& m : s.materials) material(m);
  for (const ObjectDesc& o : s.objects) {
    lines.push_back(o.loc.line);
    material(o.material);
  }
  return lines;
}

// The scene or the error, loaded with pieces of `pieceBytes`.
std::string outcome(const std::string& xml, size_t pieceBytes, std::vector<int>* lines = nullptr,
                    size_t* pieces = nullptr) {
  try {
    const SceneDesc s = loadSceneString(xml, "t.xml", {pieceBytes, pieces});
    if (lines) *lines = linesOf(s);
    return sceneToXml(s);
  } catch (const Error& e) {
    return std::string("error: ") + e.what();
  }
}

void expectSameInPieces(const std::string& xml, const std::string& what) {
  std::vector<int> wholeLines, pieceLines;
  const std::string whole = outcome(xml, kWhole, &wholeLines);
  for (size_t pieceBytes : {size_t(1), size_t(100), size_t(4096)}) {
    size_t pieces = 0;
    EXPECT_EQ(outcome(xml, pieceBytes, &pieceLines, &pieces), whole) << what << ", pieces of " << pieceBytes;
    EXPECT_EQ(pieceLines, wholeLines) << what << ", pieces of " << pieceBytes;
    // Read in pieces indeed, not parsed whole after all (as a file of small pieces should be).
    if (pieceBytes == 1 && whole.rfind("error: ", 0) != 0) {
      EXPECT_GT(pieces, 1u) << what;
    }
  }
}

std::string fileText(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(XmlSplit, EveryRepositorySceneLoadsTheSameInPieces) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(PVRT_SOURCE_DIR "/scenes"))
    if (entry.path().extension() == ".xml") {
      expectSameInPieces(fileText(entry.path()), entry.path().filename().string());
      ++n;
    }
  EXPECT_GE(n, 5);
}

// The end-to-end corpus of bad files: each one's message, line included, is the same.
TEST(XmlSplit, EveryBadFileGivesTheSameErrorInPieces) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(PVRT_SOURCE_DIR "/tests/e2e/bad")) {
    if (!entry.is_regular_file()) continue;  // bad/include/: files included by others
    const std::string xml = fileText(entry.path());
    const std::string whole = outcome(xml, kWhole);
    for (size_t pieceBytes : {size_t(1), size_t(64)})
      EXPECT_EQ(outcome(xml, pieceBytes), whole) << entry.path().filename() << ", pieces of " << pieceBytes;
    ++n;
  }
  EXPECT_GE(n, 100);
}

TEST(XmlSplit, AGeneratedSceneAndItsErrorsAreTheSameInPieces) {
  GenerateOptions g;
  g.spheres = 3000;
  const std::string xml = sceneToXml(generateScene(g));
  expectSameInPieces(xml, "3000 spheres");
  const SceneDesc whole = loadSceneString(xml, "t.xml", {kWhole});
  ASSERT_EQ(whole.objects.size(), 3001u);

  // An error deep in the file keeps its line; malformed XML further on still comes first,
  // as it does when the whole file is parsed before any element is read.
  const size_t last = xml.rfind("<sphere");
  const std::string badFlag = xml.substr(0, last) + "<sphere no_shadow=\"maybe\" " + xml.substr(last + 7);
  EXPECT_NE(outcome(badFlag, kWhole).find("no_shadow"), std::string::npos);
  expectSameInPieces(badFlag, "a bad no_shadow at the end");
  const size_t first = xml.find("<sphere");
  const size_t lastEnd = xml.rfind("</sphere>");
  const std::string badThenMalformed = xml.substr(0, first) + "<sphere no_shadow=\"maybe\" " +
                                       xml.substr(first + 7, lastEnd - first - 7) + "</sphre>" +
                                       xml.substr(lastEnd + 9);
  EXPECT_NE(outcome(badThenMalformed, kWhole).find("malformed XML"), std::string::npos);
  ASSERT_TRUE(splitXmlRoot(badThenMalformed, 1));  // the cut does not see it; tinyxml2 does
  expectSameInPieces(badThenMalformed, "a bad no_shadow, then malformed XML");
}

// Line ends of a file of several megabytes, which withLineFeeds() looks through on every
// thread: lone CRs end lines as LFs do, CR LF is one line end; an error near the end names
// the same line in all three, whole or in pieces.
TEST(XmlSplit, LoneCarriageReturnsEndLinesInABigFile) {
  GenerateOptions g;
  g.spheres = 14000;  // about 3 MB
  const std::string lf = sceneToXml(generateScene(g));
  ASSERT_GT(lf.size(), size_t(3) << 20);
  const size_t last = lf.rfind("<sphere");
  const std::string bad = lf.substr(0, last) + "<sphere no_shadow=\"maybe\" " + lf.substr(last + 7);
  auto ending = [](const std::string& text, const std::string& end) {
    std::string out;
    for (const char c : text) c == '\n' ? out += end : out += c;
    return out;
  };
  for (const std::string& text : {lf, bad}) {
    const std::string expected = outcome(text, kWhole);
    // Lone CRs everywhere, CR LF everywhere, and lone CRs only after the first 2 MB (in
    // the blocks of the scan that come last).
    const size_t late = text.find('\n', size_t(2) << 20);
    for (const std::string& other : {ending(text, "\r"), ending(text, "\r\n"),
                                     text.substr(0, late) + ending(text.substr(late), "\r")}) {
      EXPECT_EQ(outcome(other, kWhole), expected) << "whole";
      EXPECT_EQ(outcome(other, 4096), expected) << "in pieces";
    }
  }
  EXPECT_NE(outcome(bad, kWhole).find("no_shadow"), std::string::npos);
}

// Found by the fuzz target: errors the skeleton (the root, what follows it) reports must
// not come before malformed XML inside a piece, and an end tag is no place for a '<'.
TEST(XmlSplit, MalformedPiecesComeBeforeErrorsAroundTheRoot) {
  const std::string secondRoot = "\n</scene>\n<pigment color=\"1 0 0\"/>\n";
  const std::string mismatched =
      "<scene>\n<sphere center=\"0 0 0\" radius=\"1\">\n</sphre>\n<box corner1=\"0 0 0\" corner2=\"1 1 1\"/>" +
      secondRoot;
  ASSERT_TRUE(splitXmlRoot(mismatched, 1));
  EXPECT_NE(outcome(mismatched, kWhole).find("malformed XML"), std::string::npos);
  expectSameInPieces(mismatched, "a mismatched end tag, then a second root");

  const std::string lessThan = "<scene>\n<sphere center=\"0 0 0\" radius=\"1\">\n</sp<scene>" + secondRoot;
  EXPECT_FALSE(splitXmlRoot(lessThan, 1));
  expectSameInPieces(lessThan, "'<' in an end tag, then a second root");
}

// ---------------------------------------------------------------- the scan in parts

std::string describe(const std::optional<XmlSplit>& split) {
  if (!split) return "gave up";
  std::string out = std::to_string(split->bodyBegin) + "-" + std::to_string(split->bodyEnd) + ", " +
                    std::to_string(split->elements) + " elements, " + std::to_string(split->bodyLines) + " lines:";
  for (const XmlPiece& p : split->pieces)
    out += " [" + std::to_string(p.begin) + "-" + std::to_string(p.end) + " line " + std::to_string(p.firstLine) +
           " counted " + std::to_string(p.counted) + "]";
  return out;
}

// The body scanned in parts of a few sizes, from guessed places, by 1 and 2 threads, is cut
// as by one scan from its start.
void expectSameCutInParts(const std::string& xml, const std::string& what) {
  const auto counts = [](std::string_view name) { return name == "sphere" || name == "box" || name == "mesh"; };
  for (size_t pieceBytes : {size_t(1), size_t(300)}) {
    const std::string whole = describe(splitXmlRoot(xml, pieceBytes, counts, kWhole));
    for (size_t partBytes : {size_t(1), size_t(5), size_t(64), size_t(700)})
      for (int threads : {1, 2}) {
        if (partBytes == 1 && xml.size() > 2000) continue;  // (slow, and the same as parts of 5)
        if (threads == 1 && partBytes != 64) continue;      // the parts are the same, scanned in turn
        setThreadBudget(threads);
        EXPECT_EQ(describe(splitXmlRoot(xml, pieceBytes, counts, partBytes)), whole)
            << what << ": pieces of " << pieceBytes << ", parts of " << partBytes << ", " << threads << " threads";
      }
  }
  setThreadBudget(0);
}

TEST(XmlSplit, TheScanInPartsCutsAsOneScan) {
  GenerateOptions g;
  g.spheres = 40;
  const std::string generated = sceneToXml(generateScene(g));
  expectSameCutInParts(generated, "40 spheres");
  for (const char* xml : {
           "<scene><sphere/><!-- <box/> </scene> --><box a='>'/><mesh><triangle/><triangle/></mesh></scene>",
           "<scene>\n <mesh>\n  <triangle p1=\"0 0 0\"/>\n  <triangle/>\n </mesh>\n <sphere/>\n</scene>\n<!-- x -->",
           "<scene><sphere><![CDATA[ </sphere> <box/> ]]></sphere><box/></scene>",
           "<scene><sphere/></scene><scene><box/></scene>",   // a second root
           "<scene><sphere/>text<box/></scene>",              // text among the children
           "<scene><sphere/><box/>",                          // no end
           "<scene><sphere/><?pi?><box/></scene>",
           "<scene><sphere a=\"x>y<z\"><pigment/></sphere><box></box></scene>",
       })
    expectSameCutInParts(xml, xml);
  for (const auto& entry : std::filesystem::directory_iterator(PVRT_SOURCE_DIR "/scenes"))
    if (entry.path().extension() == ".xml") expectSameCutInParts(fileText(entry.path()), entry.path().string());
  for (const auto& entry : std::filesystem::directory_iterator(PVRT_SOURCE_DIR "/tests/e2e/bad"))
    if (entry.is_regular_file()) expectSameCutInParts(fileText(entry.path()), entry.path().string());
  // Mutants of the generated scene: a few bytes of markup put in or taken out anywhere.
  std::mt19937 random(7);
  const char* inserts[] = {"<", ">", "\"", "'", "</sphere>", "<!--", "-->", "<box/>", "x", "<![CDATA[", "]]>", "/>"};
  for (int i = 0; i < 60; ++i) {
    std::string xml = generated;
    const size_t at = random() % xml.size();
    if (i % 3 == 0) {
      xml.erase(at, random() % 40);
    } else {
      xml.insert(at, inserts[random() % std::size(inserts)]);
    }
    expectSameCutInParts(xml, "mutant " + std::to_string(i));
  }
}

}  // namespace
}  // namespace pvrt
