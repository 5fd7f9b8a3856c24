// Cuts a big scene file into pieces of whole top-level elements, so that the loader can
// parse it a piece at a time. tinyxml2 builds its whole tree in memory, about four bytes
// for every byte of text: a scene of a million spheres (243 MB) would take a gigabyte of
// tree at once, which is most of its load time. Pieces of a few megabytes take a few tens,
// and two or more of them can be parsed at the same time.
//
// The cut is a light scan, not an XML parser: it only has to find where the root's
// children begin and end. Anything it does not expect (a DOCTYPE, text or a processing
// instruction among the root's children, unbalanced tags, deep nesting) makes it give up,
// and the loader then parses the file whole, which reports the problem as it always has.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

namespace pvrt {

struct XmlPiece {
  size_t begin = 0, end = 0;  // byte offsets: whole elements of the root, with the space and comments around them
  int firstLine = 1;          // the file's line at `begin`
  size_t counted = 0;         // its elements whose names `counts` (below) said yes to
};

struct XmlSplit {
  size_t bodyBegin = 0;  // just after the root's start tag
  size_t bodyEnd = 0;    // where the root's end tag starts
  std::vector<XmlPiece> pieces;  // in file order, covering [bodyBegin, bodyEnd)
  size_t elements = 0;           // the root's child elements
  int bodyLines = 0;             // newlines in [bodyBegin, bodyEnd)
};

// The root's children in pieces of at least `pieceBytes` bytes (but the last), each ending
// after an element; nullopt when the scan gives up (see above). `counts`, when given, is
// asked about the name of each of the root's children (the bytes up to the first space,
// '/' or '>' of its start tag), so that a reader knows, before any piece is parsed, how many
// elements of a kind come before each piece; it is called from several threads at once.
// The scan itself runs on every thread (threadBudget()), over parts of the body of
// `partBytes` (0: a few megabytes); the result is the same for any parts and threads.
// Throws interrupt::error() when a signal comes during the scan (core/interrupt.h).
std::optional<XmlSplit> splitXmlRoot(std::string_view bytes, size_t pieceBytes,
                                     const std::function<bool(std::string_view name)>& counts = {},
                                     size_t partBytes = 0);

}  // namespace pvrt
