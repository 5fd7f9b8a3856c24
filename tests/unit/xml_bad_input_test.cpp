// Hostile input to the loader: bytes that are not text, absurd nesting, values that would
// make messages span lines, numbers and transforms beyond what the renderer can hold.
// Each must give exactly one `file:line: error:` line, never a crash.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

#include "core/error.h"
#include "scene/xml_attributes.h"
#include "scene/xml_document.h"
#include "scene/xml_loader.h"

namespace pvrt {
namespace {

std::string errorOf(const std::string& xml, size_t pieceBytes) {
  try {
    loadSceneString(xml, "t.xml", {pieceBytes});
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::SceneError);
    return e.what();
  }
  return "(no error)";
}

// The message of loading `xml` whole, which loading it in pieces of a byte (as a big file
// is, scene/xml_split.h) must repeat.
std::string errorOf(const std::string& xml) {
  const std::string whole = errorOf(xml, std::numeric_limits<size_t>::max());
  EXPECT_EQ(errorOf(xml, 1), whole) << "in pieces";
  return whole;
}

std::string inScene(const std::string& body) { return "<scene>\n" + body + "\n</scene>"; }

TEST(XmlBadInput, BytesThatAreNotTextAreRefusedWithTheirLine) {
  EXPECT_EQ(errorOf(std::string("<scene>\n<sphere/>\0</scene>", 26)),
            "t.xml:2: error: xml: control character 0x00 is not allowed (is this a binary file?)");
  EXPECT_EQ(errorOf("<scene>\n\n<sph\xff/></scene>"),
            "t.xml:3: error: xml: byte 0xff is not UTF-8 text (save the file as UTF-8)");
  // Latin-1 "é", an overlong "/" and a UTF-16 surrogate are not UTF-8 either.
  EXPECT_EQ(errorOf("<scene><!-- caf\xe9 --></scene>"),
            "t.xml:1: error: xml: byte 0xe9 is not UTF-8 text (save the file as UTF-8)");
  const std::string notUtf8 = " is not UTF-8 text (save the file as UTF-8)";
  EXPECT_EQ(errorOf("<scene>\xc0\xaf</scene>"), "t.xml:1: error: xml: byte 0xc0" + notUtf8);
  EXPECT_EQ(errorOf("<scene>\xed\xa0\x80</scene>"), "t.xml:1: error: xml: byte 0xed" + notUtf8);
  EXPECT_EQ(errorOf("\x89PNG\r\n\x1a\n"), "t.xml:1: error: xml: byte 0x89" + notUtf8);
}

TEST(XmlBadInput, CharacterReferencesToNonCharactersAreRefused) {
  // tinyxml2 would decode &#0; into a NUL that silently cuts "10" to "1".
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"1&#0;0\"/>")),
            "t.xml:2: error: xml: character reference &#0; is not an XML character");
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"&#xD800;\"/>")),
            "t.xml:2: error: xml: character reference &#xD800; is not an XML character");
  EXPECT_EQ(errorOf("<scene>\n\n<sphere center=\"0 0 0\" radius=\"&#x110000;\"/></scene>"),
            "t.xml:3: error: xml: character reference &#x110000; is not an XML character");
  // With no digits they are not XML references, yet tinyxml2 decoded them to nothing: "1&#x;0" was 10
  // and "1&#;" 1, in attributes and in text alike (blind14).
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"1&#x;0\"/>")),
            "t.xml:2: error: xml: character reference &#x; has no digits (XML writes &#N; or &#xH;)");
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"1&#;\"/>")),
            "t.xml:2: error: xml: character reference &#; has no digits (XML writes &#N; or &#xH;)");
  EXPECT_EQ(errorOf(inScene("\n<sphere center=\"0 0 0\" radius=\"1\">&#x;</sphere>")),
            "t.xml:3: error: xml: character reference &#x; has no digits (XML writes &#N; or &#xH;)");
  // Inside comments they are not references; good ones are decoded.
  EXPECT_NO_THROW(loadSceneString("<scene><!-- &#0; --><sphere center=\"0 0 0\" radius=\"&#x31;&#48;\"/></scene>"));
  EXPECT_EQ(std::get<SphereDesc>(loadSceneString("<scene><sphere center=\"0 0 0\" radius=\"&#x31;&#48;\"/></scene>")
                                     .objects.at(0)
                                     .shape)
                .radius,
            10);
}

// tinyxml2 read "< sphere/>" as <sphere/> and let "--" through inside a comment; XML allows
// neither (a name follows '<' directly; Comment excludes "--" and a final '-').
TEST(XmlBadInput, WhiteSpaceAfterLessThanAndDoubleHyphensInCommentsAreRefused) {
  EXPECT_EQ(errorOf("<scene>\n< sphere center=\"0 0 0\" radius=\"1\"/>\n</scene>"),
            "t.xml:2: error: xml: white space after '<' (an element's name follows '<' directly)");
  EXPECT_EQ(errorOf("<scene>\n<sphere center=\"0 0 0\" radius=\"1\">\n<\tpigment/></sphere></scene>"),
            "t.xml:3: error: xml: white space after '<' (an element's name follows '<' directly)");
  EXPECT_EQ(errorOf("<scene>\n\n<!-- render with --spp 9 -->\n</scene>"),
            "t.xml:3: error: xml: \"--\" inside a comment (XML does not allow it; write \"- -\")");
  EXPECT_EQ(errorOf("<scene><!-- x ---></scene>"),
            "t.xml:1: error: xml: a comment ends in \"--->\" (XML does not allow it)");
  // What is allowed: '<' with white space inside comments, CDATA and declarations; an empty
  // comment; single hyphens.
  EXPECT_NO_THROW(
      loadSceneString("<?xml version=\"1.0\" ?><!-- a < b, -x- --><!----><scene>"
                      "<!-- radius < falloff - 1 -->\n</scene >",
                      "t.xml"));
  EXPECT_EQ(errorOf("<scene><![CDATA[ < x ]]></scene>"), "t.xml:1: error: scene: unexpected text \"< x\"");
}

TEST(XmlBadInput, OnlyOneRootAndNoDeclarationsInside) {
  EXPECT_EQ(errorOf("<scene/>\n<scene><sphre/></scene>"),
            "t.xml:2: error: scene: a second root element (only one <scene> is allowed)");
  EXPECT_EQ(errorOf("<!DOCTYPE scene [<!ENTITY r \"1\">]>\n<scene/>"),
            "t.xml:1: error: xml: <!DOCTYPE> and other <!...> are not supported");
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"1\"><!ELEMENT x></sphere>")),
            "t.xml:2: error: xml: <!...> and <?...?> are not allowed inside elements");
  EXPECT_EQ(errorOf("<?xml version=\"1.0\"?>\n<?xml version=\"1.0\"?>\n<scene/>"),
            "t.xml:2: error: xml: the <?xml ...?> declaration may appear only once, first");
  EXPECT_NO_THROW(loadSceneString("<!-- before --><scene/><!-- after -->"));
}

// tinyxml2 read <sphere center="0 0 0"radius="1"/> as two attributes and skipped white space
// before <?xml ...?>; XML requires white space between attributes and nothing before the
// declaration (blind11).
TEST(XmlBadInput, AttributesWithoutWhiteSpaceBetweenThemAreRefused) {
  const std::string unseparated = "error: xml: no white space between two attributes (XML requires it)";
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\"radius=\"1\"/>")), "t.xml:2: " + unseparated);
  EXPECT_EQ(errorOf(inScene("<sphere center='0 0 0'\nradius='1'/>\n<sphere center='0 0 0'radius='1'/>")),
            "t.xml:4: " + unseparated);
  EXPECT_EQ(errorOf("<scene>\n<camera location=\"0 1 -5\">\n<rotate v='0 1 0'v='1'/></camera></scene>"),
            "t.xml:3: " + unseparated);
  // Quotes and '>' inside values, and "/>" or ">" right after the last quote, are fine.
  EXPECT_NO_THROW(
      loadSceneString("<scene><material name=\"m\"/><sphere center=\"0 0 0\" radius=\"1\" "
                      "material='m'/><!-- a\"b --><sphere\tcenter=\"0 0 0\"\nradius=\"1\" ></sphere>"
                      "</scene>"));
  EXPECT_EQ(errorOf(inScene("<material name=\"a>'b\"/>")),
            "t.xml:2: error: material: material names use letters, digits and '_' only, got \"a>'b\"");
}

// tinyxml2 read the attributes of a closing tag and dropped them, so </sphere x="1"> loaded; and
// a file of text with no markup at all was said to have "text after the <scene> element"
// (blind12).
TEST(XmlBadInput, AClosingTagHoldsOnlyItsName) {
  const std::string more = "error: xml: a closing tag holds more than its name (</name> takes no attributes)";
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"1\"></sphere x=\"1\">")), "t.xml:2: " + more);
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"1\">\n</sphere\njunk>")), "t.xml:4: " + more);
  EXPECT_NO_THROW(loadSceneString(inScene("<sphere center=\"0 0 0\" radius=\"1\"></sphere \n\t>")));
}

TEST(XmlBadInput, TheDeclarationAfterACommentOrInsideTheSceneIsNotFirst) {
  const std::string notFirst = ": error: xml: the <?xml ...?> declaration may appear only once, first";
  EXPECT_EQ(errorOf("<!-- c -->\n<?xml version=\"1.0\"?>\n<scene/>"), "t.xml:2" + notFirst);
  EXPECT_EQ(errorOf("<scene>\n\n<?xml version=\"1.0\"?>\n</scene>"), "t.xml:3" + notFirst);
  EXPECT_NO_THROW(loadSceneString("\xEF\xBB\xBF<?xml version=\"1.0\"?>\n<scene/>"));
}

TEST(XmlBadInput, AMarkupDeclarationCutShortSaysSo) {
  const std::string cut = ": error: xml: malformed XML (XML_ERROR_PARSING_UNKNOWN: a <!...> not closed by '>', such "
                          "as a comment or CDATA section cut short at its start)";
  EXPECT_EQ(errorOf("<scene>\n<!-"), "t.xml:2" + cut);
  EXPECT_EQ(errorOf("<scene>\n\n<![CDA"), "t.xml:3" + cut);
}

TEST(XmlBadInput, TextWithNoMarkupIsNotAScene) {
  EXPECT_EQ(errorOf("\n  Name:\tpvrt\nState:\tR (running)\n"),
            "t.xml:2: error: xml: not an XML scene: the file holds text (\"Name:\\tpvrt\") and no element");
  EXPECT_EQ(errorOf("hello world, this is a long line of text\n"),
            "t.xml:1: error: xml: not an XML scene: the file holds text (\"hello world, this is...\") and no element");
}

TEST(XmlBadInput, NothingButAByteOrderMarkBeforeTheDeclaration) {
  const std::string before =
      ": error: xml: white space before the <?xml ...?> declaration (it must be the file's first bytes)";
  EXPECT_EQ(errorOf("\n<?xml version=\"1.0\"?>\n<scene/>"), "t.xml:2" + before);
  EXPECT_EQ(errorOf("\xEF\xBB\xBF <?xml version=\"1.0\"?><scene/>"), "t.xml:1" + before);
  EXPECT_NO_THROW(loadSceneString("\xEF\xBB\xBF<?xml version=\"1.0\"?>\n<scene/>"));
  EXPECT_NO_THROW(loadSceneString("\n  <scene/>"));
}

// A file cut short: each of tinyxml2's errors says that the end of the file may be the cause.
TEST(XmlBadInput, FilesCutShortSaySo) {
  EXPECT_EQ(errorOf("<scene>\n<sphere center=\"0 0 0\" radius=\"1"),
            "t.xml:2: error: xml: malformed XML (XML_ERROR_PARSING_ATTRIBUTE: an attribute given twice, without "
            "quotes or '=', or the file ends inside its value)");
  EXPECT_EQ(errorOf("<scene>\n<sphere center=\"0 0 0\"\n<sph"),
            "t.xml:2: error: xml: malformed XML (XML_ERROR_PARSING_ELEMENT: a tag not closed by '>' or '/>', or the "
            "file ends inside one)");
  EXPECT_EQ(errorOf("<scene>\n</sce"),
            "t.xml:2: error: xml: malformed XML (XML_ERROR_PARSING_ELEMENT: a tag not closed by '>' or '/>', or the "
            "file ends inside one)");
  EXPECT_EQ(errorOf("<scene/>\njunk"),
            "t.xml:2: error: xml: malformed XML (XML_ERROR_PARSING_TEXT: text after the <scene> element, or the file "
            "ends before its elements are closed)");
  EXPECT_EQ(errorOf("<scene>\n<!-- a"),
            "t.xml:2: error: xml: malformed XML (XML_ERROR_PARSING_COMMENT: a comment not closed by '-->')");
  EXPECT_EQ(errorOf("<scene>\n<![CDATA[ a"),
            "t.xml:2: error: xml: malformed XML (XML_ERROR_PARSING_CDATA: a CDATA section not closed by ']]>')");
}

// tinyxml2 names the line of the element whose closing tag does not match: for a closing tag
// too many, <scene> on line 1. The message also says which closing tag, and where.
TEST(XmlBadInput, AMismatchedClosingTagIsNamedWithItsLine) {
  auto message = [](int line, const std::string& which) {
    return "t.xml:" + std::to_string(line) + ": error: xml: malformed XML (XML_ERROR_MISMATCHED_ELEMENT: " + which +
           ": an element not closed, or closed with another name)";
  };
  EXPECT_EQ(errorOf("<scene>\n<cylinder base=\"0 0 0\" cap=\"0 1 0\" radius=\"1\">\n</cylinder>\n</cylinder>\n"
                    "</scene>"),
            message(4, "<scene> of line 1 is closed by </cylinder> on line 4"));
  // Comments, CDATA, quoted '>' and empty elements do not count as tags.
  EXPECT_EQ(errorOf("<scene>\n<!-- </x> --><![CDATA[</y>]]><sphere center=\"0 0 0\" radius=\"1\">"
                    "<pigment color=\">\"/><finish>\n</sphere></finish></scene>"),
            message(3, "<finish> of line 2 is closed by </sphere> on line 3"));
}

// tinyxml2 ends a document without an error at a closing tag outside every element, so that
// the objects after a second </scene> were dropped and the scene rendered without them.
TEST(XmlBadInput, AClosingTagOutsideEveryElementIsAnError) {
  const std::string tooMany = ": error: xml: malformed XML (XML_ERROR_MISMATCHED_ELEMENT: ";
  EXPECT_EQ(errorOf("<scene>\n</scene>\n</scene>\n"),
            "t.xml:3" + tooMany + "</scene> on line 3 closes no element (a closing tag too many))");
  EXPECT_EQ(errorOf("<scene>\n<camera/>\n</scene>\n</scene>\n<sphere center=\"0 0 0\" radius=\"1\"/>\n"),
            "t.xml:4" + tooMany + "</scene> on line 4 closes no element (a closing tag too many))");
  EXPECT_EQ(errorOf("<scene/>\n</sphere>\n"),
            "t.xml:2" + tooMany + "</sphere> on line 2 closes no element (a closing tag too many))");
  // Before the root, it hid the <scene> that follows ("the file has no <scene> element").
  EXPECT_EQ(errorOf("</scene>\n<scene/>\n"),
            "t.xml:1" + tooMany + "</scene> on line 1 closes no element (a closing tag too many))");
  // A big file is read in pieces (scene/xml_split.h): the part after the pieces is checked too.
  std::string big = "<scene>\n";
  for (int i = 0; i < 50; ++i) big += "<sphere center=\"0 0 0\" radius=\"1\"/>\n";
  EXPECT_EQ(errorOf(big + "</scene>\n</scene>\n", 256),
            "t.xml:53" + tooMany + "</scene> on line 53 closes no element (a closing tag too many))");
}

// tinyxml2 reads any <?name ...?> as a declaration; only <?xml ...?>, first, is one.
TEST(XmlBadInput, ProcessingInstructionsAreRefusedByName) {
  EXPECT_EQ(errorOf("<?xml version=\"1.0\"?>\n<?xml-stylesheet href=\"a.css\"?>\n<scene/>"),
            "t.xml:2: error: xml: processing instructions (<?xml-stylesheet ...?>) are not supported");
  EXPECT_EQ(errorOf("<?pvrt hint?>\n<scene/>"),
            "t.xml:1: error: xml: processing instructions (<?pvrt ...?>) are not supported");
  EXPECT_EQ(errorOf("<scene>\n<?pvrt hint?>\n</scene>"),
            "t.xml:2: error: xml: malformed XML (XML_ERROR_PARSING_DECLARATION: a <?...?> inside an element (scenes "
            "take none), or one not closed by '?>')");
  EXPECT_NO_THROW(loadSceneString("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<scene/>"));
}

// A no-break space (or another space that is not ' ') separates nothing; quoted as it is, the
// message would show a good vector.
TEST(XmlBadInput, SpacesThatAreNotSpacesAreShownInMessages) {
  EXPECT_EQ(errorOf(inScene("<background color=\"0\xc2\xa0"
                            "1 0\"/>")),
            "t.xml:2: error: background: attribute 'color' must be a vector of 3 numbers, got \"0\\u00a01 0\"");
  EXPECT_EQ(printable("a\xe2\x80\x8b"
                      "b\xe3\x80\x80"
                      "c\xef\xbb\xbf"),
            "a\\u200bb\\u3000c\\ufeff");
  EXPECT_EQ(printable("caf\xc3\xa9 \xe2\x82\xac"), "caf\xc3\xa9 \xe2\x82\xac");  // other text as it is
}

TEST(XmlBadInput, Utf8TextIsAllowedAndQuotedIntact) {
  EXPECT_EQ(firstNonTextByte("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x8e\xa8\t\r\n"), std::string_view::npos);
  EXPECT_EQ(errorOf(inScene("<sph\xc3\xa8re/>")),
            "t.xml:2: error: sph\xc3\xa8re: unknown element (expected camera, light_source, material, an object, ...)");
  // A BOM is fine.
  EXPECT_NO_THROW(loadSceneString("\xef\xbb\xbf<scene/>"));
}

// The scan reads plain ASCII eight bytes at a time: every offset of a bad byte, within a
// word and across words, behind plain text and behind multi-byte characters, is found.
TEST(XmlBadInput, EveryBadByteIsFoundWhereverItSits) {
  const std::string plain(40, 'a');
  for (size_t at = 0; at < plain.size(); ++at) {
    for (const char bad : {'\x01', '\x1f', '\x80', '\xff'}) {
      std::string s = plain;
      s[at] = bad;
      ASSERT_EQ(firstNonTextByte(s), at) << "offset " << at << " byte " << int(static_cast<unsigned char>(bad));
    }
    std::string s = plain;
    s.replace(at, 2, "\xc3\xa9");  // a whole two-byte character: text
    if (at + 2 <= plain.size()) {
      ASSERT_EQ(firstNonTextByte(s.substr(0, plain.size())), std::string_view::npos) << "offset " << at;
    }
  }
  // Tab, newline and carriage return are text; 0x20 and 0x7e are the plain range's ends.
  EXPECT_EQ(firstNonTextByte("\t\n\r ~\t\n\r ~\t\n\r ~ ~"), std::string_view::npos);
  EXPECT_EQ(firstBadCharacterReference("no references at all, just text & more"), std::string_view::npos);
  EXPECT_EQ(firstBadCharacterReference("<a v=\"&#1;\"/>"), 6u);
}

TEST(XmlBadInput, DeepNestingIsAnErrorNotAStackOverflow) {
  std::string deep;
  for (int i = 0; i < 100000; ++i) deep += "<mesh>";
  EXPECT_EQ(errorOf("<scene>" + deep), "t.xml:1: error: xml: elements nested more than 100 deep");
}

TEST(XmlBadInput, MessagesStayOnOneLineAndShort) {
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"1\n2\"/>")),
            "t.xml:2: error: sphere: attribute 'radius' must be one number, got \"1\\n2\"");
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"1&#127;\"/>")),
            "t.xml:2: error: sphere: attribute 'radius': \"1\\x7f\" is not a number");
  const std::string longValue(100000, 'x');
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"" + longValue + "\"/>")),
            "t.xml:2: error: sphere: attribute 'radius': \"" + std::string(40, 'x') + "...\" is not a number");
  const std::string longName(1000, 'q');
  EXPECT_EQ(errorOf(inScene("<" + longName + "/>")),
            "t.xml:2: error: " + std::string(40, 'q') +
                "...: unknown element (expected camera, light_source, material, an object, ...)");
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"1\" material=\"a\tb\"/>")),
            "t.xml:2: error: sphere: no material named 'a\\tb' is defined before it");
}

TEST(XmlBadInput, PrintableCutsOnCharacterBoundaries) {
  EXPECT_EQ(printable("ab\xc3\xa9z", 3), "ab\xc3\xa9...");
  EXPECT_EQ(printable("a\x7f", 10), "a\\x7f");
  EXPECT_EQ(printable("", 10), "");
  EXPECT_EQ(printable("a\xff\xc3", 10), "a\\xff\\xc3");  // not UTF-8: escaped, never copied
}

TEST(XmlBadInput, ImageSizeAndPixelCount) {
  EXPECT_EQ(errorOf(inScene("<image width=\"-5\" height=\"10\"/>")),
            "t.xml:2: error: image: attribute 'width' must be an integer from 1 to 65536, got -5");
  EXPECT_EQ(errorOf(inScene("<image width=\"10\" height=\"2147483648\"/>")),
            "t.xml:2: error: image: attribute 'height' must be an integer from 1 to 65536, got 2147483648");
  EXPECT_EQ(errorOf(inScene("<image width=\"65536\" height=\"65536\"/>")),
            "t.xml:2: error: image: 65536 x 65536 pixels is more than 268435456");
  EXPECT_NO_THROW(loadSceneString(inScene("<image width=\"65536\" height=\"4096\"/>")));
}

TEST(XmlBadInput, TransformsThatTogetherLeaveTheRange) {
  std::string scales;
  for (int i = 0; i < 3; ++i) scales += "<scale v=\"1e6\"/>";
  EXPECT_EQ(errorOf(inScene("<sphere center=\"0 0 0\" radius=\"1\">" + scales + "</sphere>")),
            "t.xml:2: error: sphere: its transforms together scale by more than 1e15 or less than 1e-15, or move "
            "by more than 1e15");
  EXPECT_EQ(errorOf(inScene("<plane><translate v=\"1e15 0 0\"/><translate v=\"1e15 0 0\"/></plane>")),
            "t.xml:2: error: plane: its transforms together scale by more than 1e15 or less than 1e-15, or move "
            "by more than 1e15");
  EXPECT_NO_THROW(loadSceneString(inScene("<plane><scale v=\"1e7\"/><scale v=\"1e7\"/></plane>")));
}

// Each of these rendered NaN, infinite pixels or never finished before the loader refused it
// (found by the mutation test).
TEST(XmlBadInput, ValuesThatBrokeTheRenderer) {
  EXPECT_EQ(errorOf(inScene("<camera angle=\"1e-300\"/>")),
            "t.xml:2: error: camera: attribute 'angle' must be at least 1e-6 degrees, got 1e-300");
  EXPECT_NO_THROW(loadSceneString(inScene("<camera angle=\"1e-6\"/>")));
  EXPECT_EQ(errorOf(inScene("<plane><finish brilliance=\"-1e15\"/></plane>")),
            "t.xml:2: error: finish: attribute 'brilliance' must not be negative, got -1e15");
  EXPECT_EQ(errorOf(inScene("<plane><finish phong_size=\"-2\"/></plane>")),
            "t.xml:2: error: finish: attribute 'phong_size' must not be negative, got -2");
  EXPECT_EQ(errorOf(inScene("<plane><interior ior=\"2147483648\"/></plane>")),
            "t.xml:2: error: interior: attribute 'ior' must be at most 1000, got 2147483648");
  EXPECT_NO_THROW(
      loadSceneString(inScene("<plane><interior ior=\"1000\"/><finish brilliance=\"0\" phong_size=\"0\"/></plane>")));
}

TEST(XmlBadInput, FilesThatCannotBeRead) {
  EXPECT_THROW(readSceneBytes("/dev/null/x"), Error);
  try {
    readSceneBytes("/dev/zero");  // a device would be read for ever
    ADD_FAILURE() << "read /dev/zero";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "/dev/zero: error: cannot read scene: not a regular file");
  }
  // An unreadable file (checked by opening, so it also holds for root's CAP_DAC_OVERRIDE
  // when the file system refuses). Skipped when the process can read it anyway.
  const std::string path = std::string(PVRT_BINARY_DIR) + "/unreadable-scene.xml";
  std::ofstream(path) << "<scene/>";
  ::chmod(path.c_str(), 0);
  if (::access(path.c_str(), R_OK) == 0) {
    std::remove(path.c_str());
    GTEST_SKIP() << "running with the right to read any file (root): unreadable files cannot be made";
  }
  try {
    loadSceneFile(path);
    ADD_FAILURE() << "read an unreadable file";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), path + ": error: cannot read scene: Permission denied");
  }
  std::remove(path.c_str());
}

}  // namespace
}  // namespace pvrt
