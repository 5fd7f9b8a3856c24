// The XML front end: turns tinyxml2's element tree into a SceneDesc, checking every
// value as it goes. The renderer never sees XML.
#include "scene/xml_loader.h"

#include <tinyxml2.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <variant>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/prefault.h"
#include "parallel/parallel_for.h"
#include "parallel/threads.h"
#include "scene/xml_attributes.h"
#include "scene/separation.h"
#include "scene/xml_document.h"
#include "scene/xml_split.h"

namespace pvrt {

namespace {

using tinyxml2::XMLElement;

// Element names are short words that their length and first and last letters nearly always
// tell apart (a table still compares the whole name): far cheaper than hashing every byte,
// for the millions of elements of a big scene.
struct ElementNameHash {
  size_t operator()(std::string_view s) const noexcept {
    return s.empty() ? 0 : s.size() * 961 + size_t(uint8_t(s.front())) * 31 + size_t(uint8_t(s.back()));
  }
};

// Every attribute each element may carry (docs/scene-format.md). The readers below check
// the values; this table lets a misspelt name be refused before any value is read.
const std::vector<std::string_view>& knownAttributes(std::string_view element) {
  using Table = std::unordered_map<std::string_view, std::vector<std::string_view>, ElementNameHash>;
  static const Table table = [] {
    const std::vector<std::string_view> object{"material", "no_shadow"};
    auto shape = [&](std::vector<std::string_view> own) {
      own.insert(own.end(), object.begin(), object.end());
      return own;
    };
    return Table{
        {"scene", {}},
        {"include", {"file"}},
        {"image", {"width", "height"}},
        {"global_settings", {"max_trace_level", "adc_bailout", "ambient_light"}},
        {"background", {"color"}},
        {"camera", {"location", "direction", "up", "right", "sky", "look_at", "angle"}},
        {"light_source", {"location", "color", "fade_distance", "fade_power", "shadowless"}},
        {"spotlight", {"point_at", "radius", "falloff", "tightness"}},
        {"area_light", {"axis1", "axis2", "size1", "size2", "adaptive", "circular", "orient"}},
        {"material", {"name"}},
        {"pigment", {"color", "filter", "transmit"}},
        {"checker", {"color1", "filter1", "transmit1", "color2", "filter2", "transmit2"}},
        {"finish",
         {"ambient", "emission", "diffuse", "brilliance", "phong", "phong_size", "specular", "roughness", "metallic",
          "conserve_energy", "reflection"}},
        {"reflection", {"min", "max", "falloff", "fresnel", "exponent", "metallic"}},
        {"interior", {"ior", "fade_distance", "fade_power", "fade_color"}},
        {"sphere", shape({"center", "radius"})},
        {"plane", shape({"normal", "distance"})},
        {"box", shape({"corner1", "corner2"})},
        {"cylinder", shape({"base", "cap", "radius", "open"})},
        {"cone", shape({"base", "base_radius", "cap", "cap_radius", "open"})},
        {"disc", shape({"center", "normal", "radius", "hole_radius"})},
        {"triangle", shape({"p1", "p2", "p3"})},  // inside a mesh, done() refuses the object ones
        {"smooth_triangle", shape({"p1", "n1", "p2", "n2", "p3", "n3"})},
        {"mesh", object},
        {"scale", {"v"}},
        {"rotate", {"v"}},
        {"translate", {"v"}},
        {"matrix", {"v"}},
    };
  }();
  static const std::vector<std::string_view> none;
  const auto it = table.find(element);
  return it == table.end() ? none : it->second;
}

// The objects of a big file are constructed as the pieces that fill them need them, in
// order, by whichever thread needs more first (a std::vector constructs its elements in
// order), a block at a time, while the others parse pieces. Each piece faults in its own
// objects' pages itself beforehand (the kernel clears each page it hands out: 1.3 s a GiB
// on a core of the 2-core VM), so that this serial part is only the constructors; and no
// object is constructed long before its text is read, so that the objects grow as the
// text they come from is given back (SceneBytes::release).
class ObjectsBuilt {
 public:
  explicit ObjectsBuilt(std::vector<ObjectDesc>& objects) : objects_(objects) {}
  // Constructs the objects up to `count` (within their capacity) that are not yet.
  void ensure(size_t count) {
    if (built_.load(std::memory_order_acquire) >= count) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    constexpr size_t kBlock = 4096;
    while (objects_.size() < count) objects_.resize(std::min(count, objects_.size() + kBlock));
    built_.store(objects_.size(), std::memory_order_release);
  }
  // Faults in the pages of objects [first, last) (reserved, maybe not yet constructed).
  void prefault(size_t first, size_t last) const {
    if (last > first) pvrt::prefault(objects_.data() + first, (last - first) * sizeof(ObjectDesc), 1, 0);
  }

 private:
  std::vector<ObjectDesc>& objects_;
  std::mutex mutex_;
  std::atomic<size_t> built_{0};
};

// Whether a child of the root named `name` is an object (every other child is a setting, a
// light, a named material, or an error).
bool isObjectName(std::string_view name) {
  static const std::unordered_set<std::string_view, ElementNameHash> shapes{
      "sphere", "plane", "box", "cylinder", "cone", "disc", "triangle", "smooth_triangle", "mesh"};
  return shapes.count(name) > 0;
}

// A piece of a big file is read on its own, ahead of its turn (Loader::Mode::Ahead). What
// such a reading cannot do, because it depends on the elements before the piece (a second
// <camera>, a material's name already taken, a reference to a material), it leaves to the
// in-order pass as one of these, already converted, in file order.
struct Background {
  Color color;
};
struct MaterialUse {
  size_t object;     // the referring object's index in SceneDesc::objects
  std::string name;  // the material's
};
struct Pending {
  std::variant<CameraDesc, GlobalSettings, Background, ImageDesc, LightDesc, MaterialDesc, MaterialUse> item;
  SourceLoc loc;        // the element's, for its errors
  std::string element;  // its name, as errors show it
};

// What reading one piece ahead of its turn gave.
struct PieceRead {
  bool text = false;        // checkSceneText() would pass the piece
  bool wellFormed = false;  // tinyxml2 parsed it
  size_t elements = 0;      // its first elements, read; the next one (if any) failed, and is read again in order
  size_t objects = 0;       // the objects among them, in their places in SceneDesc::objects
  bool complete = false;    // every element was read
  bool miscounted = false;  // the split's count of objects was not the piece's (then the file is read whole)
  std::vector<Pending> pending;
  std::exception_ptr failure;  // anything but a scene error (no memory, say)
};

// The split counted an object that the piece did not hold, or the other way round.
struct Miscounted {};

std::string withLineFeeds(std::string_view bytes);

// Included files nest at most this deep (a chain of includes that never ends is a cycle,
// which is refused first; this bounds a long chain of distinct files).
constexpr size_t kMaxIncludeDepth = 16;
// Includes read in all, each time a file is included counting once: files that include
// the next one several times over (not a cycle, and 16 deep) would otherwise be read 4^16
// times, a load that never ends. Together they may hold at most what one scene file may.
constexpr size_t kMaxIncludes = 10000;

class Loader {
 public:
  // InOrder: elements are read in file order, each knowing everything before it. Ahead: a
  // piece is read before the pieces in front of it, and leaves what depends on them pending.
  enum class Mode { InOrder, Ahead };

  explicit Loader(FileName file, Mode mode = Mode::InOrder) : file_(file), ahead_(mode == Mode::Ahead) {
    including_.push_back({file.str(), identity(file.str())});
  }

  // The whole file as one tree.
  SceneDesc load(const tinyxml2::XMLDocument& doc) {
    const XMLElement* root = begin(doc);
    // Room for every element up front: a scene of a million objects would otherwise be
    // moved about twenty times as the vector grows, each time into fresh memory.
    size_t elements = 0;
    for (const XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) ++elements;
    scene_.objects.reserve(elements);
    for (const XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) element(e);
    return std::move(scene_);
  }

  // The file a piece at a time (scene/xml_split.h): `skeleton` is the file with the root's
  // children blanked out (their lines kept), `pieces` hold them. Every thread reads pieces on
  // its own, each into its objects' places in the scene (known from the split's counts) and
  // leaving what depends on earlier pieces pending; then one pass in file order settles the
  // pending elements and reads again, from its failing element on, any piece that failed.
  // So the scene and its first error are those of load(), whatever the number of threads.
  // nullopt when a piece is not XML text or not well-formed XML: only the whole file's parse
  // can then tell which error comes first. `release`, when given, is told each piece that
  // was read whole, whose text is not read again (but for the whole file's parse, after a
  // nullopt).
  std::optional<SceneDesc> loadPieces(const tinyxml2::XMLDocument& skeleton, std::string_view bytes,
                                      const XmlSplit& split, const std::function<void(size_t, size_t)>& release) {
    const size_t count = split.pieces.size();
    // The root's errors come after any malformed XML, but before any element's.
    std::exception_ptr rootError;
    try {
      const XMLElement* root = begin(skeleton);
      if (root->FirstChildElement()) return std::nullopt;  // the skeleton's root should be empty
    } catch (const Error&) {
      rootError = std::current_exception();
    }
    std::vector<size_t> first(count + 1, 0);  // piece k's objects go to [first[k], first[k + 1])
    for (size_t k = 0; k < count; ++k) first[k + 1] = first[k] + split.pieces[k].counted;
    if (!rootError) scene_.objects.reserve(first[count]);
    // The pieces write their objects through this, never through the vector being resized.
    ObjectDesc* const places = scene_.objects.data();

    ObjectsBuilt built(scene_.objects);
    std::vector<PieceRead> reads(count);
    parallelIndices(count, 0, [&](size_t k) {
      PieceRead& read = reads[k];
      // After a signal the pieces left are skipped, not parsed (checked after the loop).
      if (interrupt::requested()) return;
      try {
        const XmlPiece& p = split.pieces[k];
        const std::string_view text = bytes.substr(p.begin, p.end - p.begin);
        read.text = isSceneText(text);
        if (!read.text) return;
        tinyxml2::XMLDocument doc;
        read.wellFormed = doc.Parse(text.data(), text.size()) == tinyxml2::XML_SUCCESS;
        if (!read.wellFormed || rootError || interrupt::requested()) return;
        built.prefault(first[k], first[k + 1]);
        built.ensure(first[k + 1]);
        Loader(file_, Mode::Ahead).readAhead(doc, p.firstLine - 1, places, first[k], first[k + 1], read);
        if (read.complete && release) release(p.begin, p.end);
      } catch (const Miscounted&) {
        read.miscounted = true;
      } catch (...) {
        read.failure = std::current_exception();
      }
    });
    interrupt::check();  // before anything would read the file again whole
    for (const PieceRead& read : reads)
      if (!read.text || !read.wellFormed || read.miscounted) return std::nullopt;
    for (const PieceRead& read : reads)
      if (read.failure) std::rethrow_exception(read.failure);
    if (rootError) std::rethrow_exception(rootError);
    built.ensure(first[count]);

    try {
      for (size_t k = 0; k < count; ++k) {
        PieceRead& read = reads[k];
        for (Pending& p : read.pending) settle(std::move(p));
        if (read.complete) {
          if (first[k] + read.objects != first[k + 1]) return std::nullopt;
          continue;
        }
        // Its element number read.elements failed: read again from there, in order.
        const XmlPiece& p = split.pieces[k];
        tinyxml2::XMLDocument doc;
        if (doc.Parse(bytes.data() + p.begin, p.end - p.begin) != tinyxml2::XML_SUCCESS) return std::nullopt;
        const XMLElement* e = doc.FirstChildElement();
        for (size_t i = 0; i < read.elements && e; ++i) e = e->NextSiblingElement();
        lineOffset_ = p.firstLine - 1;
        placeIn(scene_.objects.data(), first[k] + read.objects, first[k + 1]);
        for (; e; e = e->NextSiblingElement()) element(e);
        if (next_ != end_) return std::nullopt;
      }
    } catch (const Miscounted&) {
      return std::nullopt;
    }
    places_ = nullptr;
    lineOffset_ = 0;
    return std::move(scene_);
  }

 private:
  // Reads the elements of a piece parsed on its own (Mode::Ahead), its objects into
  // objects[first, last), into `read`; stops at the first element that fails.
  void readAhead(const tinyxml2::XMLDocument& doc, int lineOffset, ObjectDesc* objects, size_t first, size_t last,
                 PieceRead& read) {
    lineOffset_ = lineOffset;
    placeIn(objects, first, last);
    read.complete = true;
    for (const XMLElement* e = doc.FirstChildElement(); e; e = e->NextSiblingElement(), ++read.elements) {
      try {
        element(e);
      } catch (const Error&) {
        if (interrupt::requested()) throw;  // not the element's fault: the piece ends here
        read.complete = false;  // the in-order pass reads it again, and fails there or earlier
        break;
      }
    }
    if (read.complete && next_ != end_) throw Miscounted{};
    read.objects = next_ - first;
    read.pending = std::move(pending_);
  }

  // Objects go to objects[next, last) instead of being appended.
  void placeIn(ObjectDesc* objects, size_t next, size_t last) {
    places_ = objects;
    next_ = next;
    end_ = last;
  }
  void add(ObjectDesc&& o) {
    if (!places_) {
      scene_.objects.push_back(std::move(o));
      return;
    }
    if (next_ == end_) throw Miscounted{};
    places_[next_++] = std::move(o);
  }

  // Mode::Ahead: leaves what `e` gave to the in-order pass.
  template <class Item>
  void defer(const XMLElement* e, Item&& item) {
    pending_.push_back({std::forward<Item>(item), locOf(e), printable(e->Name())});
  }

  // The in-order pass: what an element read ahead left pending, checked and applied as
  // element() would have.
  void settle(Pending&& p) {
    auto fail = [&](const std::string& what) { return sceneError(p.loc, p.element, what); };
    auto onlyOnce = [&](bool& seen) {
      if (seen) throw fail("may appear only once");
      seen = true;
    };
    if (auto* c = std::get_if<CameraDesc>(&p.item)) {
      onlyOnce(haveCamera_);
      scene_.camera = std::move(*c);
    } else if (auto* g = std::get_if<GlobalSettings>(&p.item)) {
      onlyOnce(haveGlobals_);
      scene_.globals = *g;
    } else if (auto* b = std::get_if<Background>(&p.item)) {
      onlyOnce(haveBackground_);
      scene_.background = b->color;
    } else if (auto* i = std::get_if<ImageDesc>(&p.item)) {
      if (scene_.image) throw fail("may appear only once");
      scene_.image = *i;
    } else if (auto* l = std::get_if<LightDesc>(&p.item)) {
      scene_.lights.push_back(std::move(*l));
    } else if (auto* m = std::get_if<MaterialDesc>(&p.item)) {
      if (const auto taken = materialNamed(m->name)) throw fail(alreadyDefined(m->name, *taken));
      addMaterial(std::move(*m));
    } else if (auto* u = std::get_if<MaterialUse>(&p.item)) {
      const auto index = materialNamed(u->name);
      if (!index) throw fail(notDefined(u->name));
      ObjectDesc& o = scene_.objects[u->object];
      o.namedMaterial = int(*index);
      o.material = scene_.materials[*index];
    }
  }

  // The named material called `name`: its index in scene_.materials.
  std::optional<size_t> materialNamed(const std::string& name) const {
    const auto it = materialIndex_.find(name);
    if (it == materialIndex_.end()) return std::nullopt;
    return it->second;
  }
  void addMaterial(MaterialDesc&& m) {
    materialIndex_.emplace(m.name, scene_.materials.size());
    scene_.materials.push_back(std::move(m));
  }
  std::string alreadyDefined(const std::string& name, size_t other) const {
    const SourceLoc& at = scene_.materials[other].loc;
    return "material '" + name + "' is already defined at " +
           (at.file == file_ ? "line " + std::to_string(at.line) : at.str());
  }
  static std::string notDefined(const std::string& name) {
    return "no material named '" + printable(name) + "' is defined before it";
  }

  // The checks of the document and its root; the root.
  const XMLElement* begin(const tinyxml2::XMLDocument& doc) {
    const XMLElement* root = doc.RootElement();
    if (!root) throw sceneError({file_, 1}, "scene", "the file has no <scene> element");
    // tinyxml2 keeps whatever follows the root; XML allows only comments there.
    for (const tinyxml2::XMLNode* n = doc.FirstChild(); n; n = n->NextSibling()) {
      const SourceLoc at{file_, n->GetLineNum()};
      if (n->ToUnknown()) throw sceneError(at, "xml", "<!DOCTYPE> and other <!...> are not supported");
      if (const auto* d = n->ToDeclaration()) {
        // tinyxml2 reads any <?name ...?> as a declaration: a processing instruction too.
        const std::string_view v = d->Value();
        if (v.substr(0, 3) != "xml" || (v.size() > 3 && v[3] != ' ' && v[3] != '\t' && v[3] != '\r' && v[3] != '\n'))
          throw sceneError(
              at, "xml",
              "processing instructions (<?" + printable(v.substr(0, v.find(' ')), 40) + " ...?>) are not supported");
        if (n != doc.FirstChild())
          throw sceneError(at, "xml", "the <?xml ...?> declaration may appear only once, first");
      }
      if (n->ToElement() && n != root)
        throw sceneError(at, printable(n->Value()), "a second root element (only one <scene> is allowed)");
      // tinyxml2 refuses text after the root but keeps text before it (a second byte order
      // mark, "junk<scene>"), which XML does not allow either.
      if (const auto* t = n->ToText()) {
        const std::string_view v = t->Value();
        const size_t from = v.find_first_not_of(" \t\r\n");
        if (from == std::string_view::npos) continue;
        const size_t to = v.find_last_not_of(" \t\r\n");
        throw sceneError(
            {file_, n->GetLineNum()}, "xml",
            "unexpected text \"" + printable(v.substr(from, to + 1 - from), 20) + "\" outside the <scene> element");
      }
    }
    if (std::strcmp(root->Name(), "scene") != 0)
      throw sceneError(locOf(root), printable(root->Name()), "the root element must be <scene>");
    attrs(root).done();
    noText(root);
    scene_.path = file_.str();
    return root;
  }

  // One child of the root.
  void element(const XMLElement* e) {
    interrupt::check();  // a million elements take seconds
    noText(e);
    const std::string_view name = e->Name();
    // Read ahead, the checks that depend on earlier elements wait for settle().
    if (name == "camera") {
      if (ahead_) return defer(e, camera(e));
      once(e, haveCamera_);
      scene_.camera = camera(e);
    } else if (name == "global_settings") {
      if (ahead_) return defer(e, globals(e));
      once(e, haveGlobals_);
      scene_.globals = globals(e);
    } else if (name == "background") {
      if (!ahead_) once(e, haveBackground_);
      Attributes a = attrs(e);
      const Color color = a.color("color", {0, 0, 0});
      a.done();
      noChildren(e);
      if (ahead_) return defer(e, Background{color});
      scene_.background = color;
    } else if (name == "image") {
      if (ahead_) return defer(e, image(e));
      if (scene_.image) throw sceneError(locOf(e), std::string(name), "may appear only once");
      scene_.image = image(e);
    } else if (name == "light_source") {
      if (ahead_) return defer(e, light(e));
      scene_.lights.push_back(light(e));
    } else if (name == "material") {
      if (ahead_) return defer(e, namedMaterial(e));
      addMaterial(namedMaterial(e));
    } else if (name == "include") {
      include(e);
    } else {
      std::optional<std::string> use;  // read ahead: the named material it uses, pending
      add(object(e, use));
      if (use) defer(e, MaterialUse{next_ - 1, std::move(*use)});
    }
  }

  // <include file="..."/>: the children of another file's <scene>, read here as if written
  // in place (so its materials are known after it, and a second camera in it is refused).
  // The path is relative to the including file's folder; messages about what is in the
  // file name that file and its lines.
  void include(const XMLElement* e) {
    // A piece read on its own has room for the objects the split counted in it, and an
    // included file's are not among them: the file is then read whole (it is not big).
    if (places_) throw Miscounted{};
    Attributes a = attrs(e);
    const std::string file = a.text("file");
    a.done();
    noChildren(e);
    if (file.empty()) throw errorAt(e, "the file attribute is empty");
    namespace fs = std::filesystem;
    const std::string path =
        fs::path(file).is_absolute() ? file : (fs::path(file_.str()).parent_path() / file).lexically_normal().string();
    const std::string id = identity(path);
    std::string chain;
    for (const Including& i : including_) chain += printableName(i.name) + " -> ";
    chain += printableName(path);
    for (const Including& i : including_)
      if (!id.empty() && i.id == id) throw errorAt(e, "\"" + printable(file) + "\" makes a cycle: " + chain);
    if (including_.size() > kMaxIncludeDepth)
      throw errorAt(e, "more than " + std::to_string(kMaxIncludeDepth) + " nested includes: " + chain);
    if (++includesRead_ > kMaxIncludes)
      throw errorAt(e, "more than " + std::to_string(kMaxIncludes) +
                           " files included in all (each time a file is included counts)");
    // Only regular files: a pipe or a device (/dev/stdin) could keep the loader waiting.
    std::error_code ec;
    if (fs::exists(path, ec) && !fs::is_regular_file(path, ec))
      throw errorAt(e, "cannot include \"" + printable(file) + "\": not a regular file");
    std::string bytes;
    try {
      bytes = readSceneBytes(path);
    } catch (const Error& err) {
      if (err.code() != ExitCode::SceneError) throw;  // a signal: not the include's fault
      // Its message is "PATH: error: cannot read scene: WHY": the path again (in full, however
      // long) and a second "error:"; only WHY is news.
      const std::string_view what = err.what();
      constexpr std::string_view kRead = ": error: cannot read scene: ";
      const size_t at = what.rfind(kRead);
      throw errorAt(e, "cannot include \"" + printable(file) +
                           "\": " + std::string(at == std::string_view::npos ? what : what.substr(at + kRead.size())));
    }
    if ((includedBytes_ += bytes.size()) > kMaxSceneBytes)
      throw errorAt(e, "the included files hold more than 1 GiB in all");
    std::string_view text = bytes;
    const std::string lineFeeds = withLineFeeds(text);
    if (!lineFeeds.empty()) text = lineFeeds;
    checkSceneText(text, path);
    tinyxml2::XMLDocument doc;
    parseCheckedText(doc, text, path);
    const FileName outer = file_;
    const std::string scenePath = scene_.path;
    file_ = FileName(path);
    including_.push_back({path, id});
    const XMLElement* root = begin(doc);
    for (const XMLElement* c = root->FirstChildElement(); c; c = c->NextSiblingElement()) element(c);
    including_.pop_back();
    file_ = outer;
    scene_.path = scenePath;
  }
  // What makes two names one file (its canonical path), or "" when it has none.
  static std::string identity(const std::string& path) {
    std::error_code ec;
    const std::filesystem::path p = std::filesystem::weakly_canonical(path, ec);
    return ec ? std::string() : p.string();
  }

  SourceLoc locOf(const XMLElement* e) const { return {file_, e->GetLineNum() + lineOffset_}; }
  Error errorAt(const XMLElement* e, const std::string& what) const {
    return sceneError(locOf(e), printable(e->Name()), what);
  }
  Attributes attrs(const XMLElement* e) const {
    return Attributes(e, file_, knownAttributes(e->Name()), lineOffset_);
  }

  void once(const XMLElement* e, bool& seen) const {
    if (seen) throw errorAt(e, "may appear only once");
    seen = true;
  }
  // Character data is never meaningful in the format; it is almost always a typo. Nor are
  // <!...> declarations, which tinyxml2 keeps as unknown nodes.
  void noText(const XMLElement* e) const {
    for (const tinyxml2::XMLNode* n = e->FirstChild(); n; n = n->NextSibling())
      if (n->ToUnknown() || n->ToDeclaration()) {
        throw sceneError({file_, n->GetLineNum() + lineOffset_}, "xml",
                         "<!...> and <?...?> are not allowed inside elements");
      } else if (const auto* t = n->ToText()) {
        const std::string_view s = t->Value();
        const size_t from = s.find_first_not_of(" \t\r\n");
        if (from == std::string_view::npos) continue;
        const size_t to = s.find_last_not_of(" \t\r\n");
        // The line of the text itself, not of its element (which may be <scene>, on line 1):
        // tinyxml2 numbers a text node by its first character that is not white space.
        throw sceneError({file_, n->GetLineNum() + lineOffset_}, printable(e->Name()),
                         "unexpected text \"" + printable(s.substr(from, to + 1 - from), 20) + "\"");
      }
  }
  void noChildren(const XMLElement* e) const {
    noText(e);
    if (const XMLElement* c = e->FirstChildElement())
      throw errorAt(c, std::string("unexpected element inside <") + e->Name() + ">");
  }

  ImageDesc image(const XMLElement* e) {
    Attributes a = attrs(e);
    ImageDesc d;
    d.loc = a.loc();
    if (!a.has("width")) throw a.missing("width");
    if (!a.has("height")) throw a.missing("height");
    d.width = a.integer("width", 0, 1, 65536);
    d.height = a.integer("height", 0, 1, 65536);
    if (static_cast<long long>(d.width) * d.height > ImageDesc::kMaxPixels)
      throw a.error(std::to_string(d.width) + " x " + std::to_string(d.height) + " pixels is more than " +
                    std::to_string(ImageDesc::kMaxPixels));
    a.done();
    noChildren(e);
    return d;
  }

  GlobalSettings globals(const XMLElement* e) {
    Attributes a = attrs(e);
    GlobalSettings g;
    g.loc = a.loc();
    g.maxTraceLevel = a.integer("max_trace_level", g.maxTraceLevel, 1, 256);
    g.adcBailout = a.nonNegative("adc_bailout", g.adcBailout);
    g.ambientLight = a.color("ambient_light", g.ambientLight);
    a.done();
    noChildren(e);
    return g;
  }

  CameraDesc camera(const XMLElement* e) {
    Attributes a = attrs(e);
    CameraDesc c;
    c.loc = a.loc();
    c.location = a.vec("location", c.location);
    c.direction = a.nonZeroVec("direction", c.direction);
    c.up = a.nonZeroVec("up", c.up);
    c.right = a.nonZeroVec("right", c.right);
    c.sky = a.nonZeroVec("sky", c.sky);
    if (a.has("look_at")) {
      c.lookAt = a.vec("look_at");
      if (const auto why = tooClose(c.location, *c.lookAt)) throw a.error("look_at must differ from location" + *why);
    }
    if (a.has("angle")) {
      c.angle = a.number("angle");
      if (!(*c.angle > 0 && *c.angle < 180)) throw a.error("attribute 'angle' must lie between 0 and 180 degrees");
      // The direction's length is |right| / (2 tan(angle/2)): below about 1e-150 degrees its
      // square overflows, rays turn to NaN and the render never ends.
      if (*c.angle < 1e-6)
        throw a.error("attribute 'angle' must be at least 1e-6 degrees, got " + printable(e->Attribute("angle")));
    }
    a.done();
    // Nearly parallel, they would squeeze the image into a line (unit vectors first: their
    // cross product must not underflow).
    if (!(length(cross(unitDirection(c.up), unitDirection(c.right))) > kMinRelativeSeparation))
      throw a.error("up and right must not be parallel");
    c.transforms = transformsOnly(e);
    return c;
  }

  LightDesc light(const XMLElement* e) {
    Attributes a = attrs(e);
    LightDesc l;
    l.loc = a.loc();
    l.location = a.vec("location");
    l.color = a.color("color", l.color);
    l.fadeDistance = a.nonNegative("fade_distance", 0);
    l.fadePower = a.nonNegative("fade_power", 0);
    l.shadowless = a.boolean("shadowless", false);
    a.done();
    noText(e);
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      const std::string_view name = c->Name();
      if (name != "spotlight" && name != "area_light")
        throw errorAt(c, "unknown element inside <light_source> (expected spotlight or area_light)");
      Attributes b = attrs(c);
      if (name == "spotlight") {
        if (l.spot) throw errorAt(c, "may appear only once");
        SpotlightDesc s;
        s.pointAt = b.vec("point_at", s.pointAt);
        s.radius = b.number("radius", s.radius);
        s.falloff = b.number("falloff", s.falloff);
        s.tightness = b.nonNegative("tightness", s.tightness);
        if (s.radius < 0 || s.radius > 90 || s.falloff < 0 || s.falloff > 90)
          throw b.error("radius and falloff must lie between 0 and 90 degrees");
        if (const auto why = tooClose(l.location, s.pointAt))
          throw b.error("point_at must differ from the light's location" + *why);
        l.spot = s;
      } else if (name == "area_light") {
        if (l.area) throw errorAt(c, "may appear only once");
        AreaLightDesc d;
        d.axis1 = b.vec("axis1");
        d.axis2 = b.vec("axis2");
        d.size1 = b.integer("size1", 1, 1, 1024);
        d.size2 = b.integer("size2", 1, 1, 1024);
        d.adaptive = b.integer("adaptive", d.adaptive, 0, 100);
        d.circular = b.boolean("circular", false);
        d.orient = b.boolean("orient", false);
        if ((d.circular || d.orient) && (d.size1 < 2 || d.size2 < 2))
          throw b.error("a circular or oriented area light needs size1 and size2 of at least 2");
        l.area = d;
      }
      b.done();
      noChildren(c);
    }
    return l;
  }

  MaterialDesc namedMaterial(const XMLElement* e) {
    Attributes a = attrs(e);
    MaterialDesc m;
    m.loc = a.loc();
    m.name = a.text("name");
    if (m.name.empty() || m.name.find_first_not_of(
                              "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") !=
                              std::string::npos)
      throw a.error("material names use letters, digits and '_' only, got \"" + printable(m.name) + "\"");
    if (!ahead_)
      if (const auto other = materialNamed(m.name)) throw a.error(alreadyDefined(m.name, *other));
    a.done();
    noText(e);
    bool pig = false, fin = false, inte = false;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
      if (!materialPart(c, m, pig, fin, inte))
        throw errorAt(c, "unknown element inside <material> (expected pigment, finish or interior)");
    return m;
  }

  // Reads a pigment, finish or interior into `m`; false when `c` is none of them.
  bool materialPart(const XMLElement* c, MaterialDesc& m, bool& pig, bool& fin, bool& inte) {
    const std::string_view name = c->Name();
    if (name == "pigment") {
      once(c, pig);
      m.pigment = pigment(c);
    } else if (name == "finish") {
      once(c, fin);
      m.finish = finishes_.share(finish(c));
    } else if (name == "interior") {
      once(c, inte);
      m.interior = interiors_.share(interior(c));
    } else {
      return false;
    }
    return true;
  }

  FilterColor filterColor(Attributes& a, const char* color, const char* filter, const char* transmit,
                          FilterColor fallback) {
    FilterColor f = fallback;
    f.rgb = a.color(color, f.rgb);
    f.filter = a.number(filter, f.filter);
    f.transmit = a.number(transmit, f.transmit);
    return f;
  }

  PigmentDesc pigment(const XMLElement* e) {
    Attributes a = attrs(e);
    PigmentDesc p;
    p.loc = a.loc();
    p.color = filterColor(a, "color", "filter", "transmit", p.color);
    a.done();
    noText(e);
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (transformStep(c, p.transforms)) continue;
      if (std::strcmp(c->Name(), "checker") != 0)
        throw errorAt(c, "unknown element inside <pigment> (expected checker or a transform)");
      if (p.checker) throw errorAt(c, "may appear only once");
      if (e->Attribute("color") || e->Attribute("filter") || e->Attribute("transmit"))
        throw errorAt(c, "a checker pigment takes its colours from <checker>, not from <pigment>");
      Attributes b = attrs(c);
      CheckerDesc k;
      k.color1 = filterColor(b, "color1", "filter1", "transmit1", k.color1);
      k.color2 = filterColor(b, "color2", "filter2", "transmit2", k.color2);
      b.done();
      noChildren(c);
      p.checker = std::make_shared<const CheckerDesc>(k);
    }
    checkSingular(e, p.transforms);
    return p;
  }

  FinishDesc finish(const XMLElement* e) {
    Attributes a = attrs(e);
    FinishDesc f;
    f.ambient = a.color("ambient", f.ambient);
    f.emission = a.color("emission", f.emission);
    f.diffuse = a.number("diffuse", f.diffuse);
    // Exponents of a cosine: negative ones are infinite at grazing angles.
    f.brilliance = a.nonNegative("brilliance", f.brilliance);
    f.phong = a.number("phong", f.phong);
    f.phongSize = a.nonNegative("phong_size", f.phongSize);
    f.specular = a.number("specular", f.specular);
    f.roughness = a.positive("roughness", f.roughness);
    f.metallic = a.number("metallic", f.metallic);
    f.conserveEnergy = a.boolean("conserve_energy", false);
    const bool flat = a.has("reflection");
    if (flat) {
      const Color r = a.color("reflection", {});
      f.reflection.min = f.reflection.max = r;
    }
    a.done();
    noText(e);
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (std::strcmp(c->Name(), "reflection") != 0)
        throw errorAt(c, "unknown element inside <finish> (expected reflection)");
      if (flat) throw errorAt(c, "give reflection either as an attribute or as an element, not both");
      Attributes b = attrs(c);
      ReflectionDesc& r = f.reflection;
      r.min = b.color("min", r.min);
      r.max = b.color("max", r.min);  // one value means the same at every angle
      r.falloff = b.positive("falloff", r.falloff);
      r.fresnel = b.boolean("fresnel", false);
      r.exponent = b.positive("exponent", r.exponent);
      r.metallic = b.number("metallic", r.metallic);
      b.done();
      noChildren(c);
    }
    return f;
  }

  InteriorDesc interior(const XMLElement* e) {
    Attributes a = attrs(e);
    InteriorDesc in;
    in.ior = a.positive("ior", in.ior);
    // Far beyond any material; at about 1e9 the refraction overflows to infinite pixels.
    if (in.ior > 1000) throw a.error("attribute 'ior' must be at most 1000, got " + printable(e->Attribute("ior")));
    in.fadeDistance = a.nonNegative("fade_distance", in.fadeDistance);
    in.fadePower = a.nonNegative("fade_power", in.fadePower);
    in.fadeColor = a.color("fade_color", in.fadeColor);
    a.done();
    noChildren(e);
    return in;
  }

  // A transform child; false when `c` is not a transform.
  bool transformStep(const XMLElement* c, TransformList& list) {
    const std::string_view name = c->Name();
    TransformStep s{};
    if (name == "scale") s.kind = TransformStep::Kind::Scale;
    else if (name == "rotate") s.kind = TransformStep::Kind::Rotate;
    else if (name == "translate") s.kind = TransformStep::Kind::Translate;
    else if (name == "matrix") s.kind = TransformStep::Kind::Matrix;
    else return false;
    Attributes a = attrs(c);
    s.loc = a.loc();
    if (s.kind == TransformStep::Kind::Matrix) {
      if (!a.has("v")) throw a.missing("v");
      const auto w = words(c->Attribute("v"));
      if (w.size() != 12) throw a.error("attribute 'v' must hold 12 numbers, got " + std::to_string(w.size()));
      for (size_t i = 0; i < 12; ++i) s.matrix[i] = a.parseNumber("v", w[i]);
      if (!s.affine().inverse()) throw a.error("the matrix is singular");
    } else {
      s.v = s.kind == TransformStep::Kind::Scale ? a.vecOrScalar("v") : a.vec("v");
      if (s.kind == TransformStep::Kind::Scale && (s.v.x == 0 || s.v.y == 0 || s.v.z == 0))
        throw a.error("a scale factor of zero flattens the object");
    }
    a.done();
    noChildren(c);
    list.steps.push_back(s);
    return true;
  }

  TransformList transformsOnly(const XMLElement* e) {
    TransformList list;
    noText(e);
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
      if (!transformStep(c, list))
        throw errorAt(c, std::string("unknown element inside <") + e->Name() + "> (expected a transform)");
    checkSingular(e, list);
    return list;
  }

  // The product must be invertible, and neither it nor its inverse may reach beyond
  // kMaxSceneNumber: each step is in range, but many of them could multiply to inf.
  void checkSingular(const XMLElement* e, const TransformList& list) const {
    if (list.empty()) return;
    const Affine m = list.combined();
    const auto inverse = m.inverse();
    if (!inverse) throw errorAt(e, "its transforms together are singular");
    auto bounded = [](const Affine& a) {
      bool ok = std::fabs(a.t.x) <= kMaxSceneNumber && std::fabs(a.t.y) <= kMaxSceneNumber &&
                std::fabs(a.t.z) <= kMaxSceneNumber;
      for (const auto& row : a.m)
        for (double v : row) ok = ok && std::fabs(v) <= kMaxSceneNumber;
      return ok;
    };
    if (!bounded(m) || !bounded(*inverse))
      throw errorAt(e, "its transforms together scale by more than 1e15 or less than 1e-15, or move by more than 1e15");
  }

  // Read ahead, a named material's name goes to `use` instead of its copy to the object.
  ObjectDesc object(const XMLElement* e, std::optional<std::string>& use) {
    const std::string_view name = e->Name();
    if (!isObjectName(name))
      throw errorAt(e, "unknown element (expected camera, light_source, material, an object, ...)");
    Attributes a = attrs(e);
    ObjectDesc o;
    o.loc = a.loc();
    if (name == "sphere") {
      SphereDesc s;
      s.center = a.vec("center");
      s.radius = a.positive("radius");
      o.shape = s;
    } else if (name == "plane") {
      PlaneDesc p;
      p.normal = a.nonZeroVec("normal", p.normal);
      p.distance = a.number("distance", 0);
      o.shape = p;
    } else if (name == "box") {
      o.shape = BoxDesc{a.vec("corner1"), a.vec("corner2")};
    } else if (name == "cylinder") {
      CylinderDesc c;
      c.base = a.vec("base");
      c.cap = a.vec("cap");
      c.radius = a.positive("radius");
      c.open = a.boolean("open", false);
      if (const auto why = tooClose(c.base, c.cap)) throw a.error("base and cap must differ" + *why);
      o.shape = c;
    } else if (name == "cone") {
      ConeDesc c;
      c.base = a.vec("base");
      c.baseRadius = a.nonNegative("base_radius", c.baseRadius);
      c.cap = a.vec("cap");
      c.capRadius = a.nonNegative("cap_radius", c.capRadius);
      c.open = a.boolean("open", false);
      if (const auto why = tooClose(c.base, c.cap)) throw a.error("base and cap must differ" + *why);
      if (c.baseRadius == 0 && c.capRadius == 0) throw a.error("base_radius and cap_radius cannot both be 0");
      o.shape = c;
    } else if (name == "disc") {
      DiscDesc d;
      d.center = a.vec("center");
      d.normal = a.nonZeroVec("normal", d.normal);
      d.radius = a.positive("radius");
      d.holeRadius = a.nonNegative("hole_radius", 0);
      if (d.holeRadius >= d.radius) throw a.error("hole_radius must be smaller than radius");
      o.shape = d;
    } else if (name == "triangle") {
      o.shape = triangle(a);
    } else if (name == "smooth_triangle") {
      o.shape = smoothTriangle(a);
    } else {
      o.shape = MeshDesc{};
    }
    const bool named = a.has("material");
    if (named) {
      std::string ref = a.text("material");
      if (ahead_) {
        use = std::move(ref);
      } else {
        const auto index = materialNamed(ref);
        if (!index) throw a.error(notDefined(ref));
        o.namedMaterial = int(*index);
        o.material = scene_.materials[*index];
      }
    }
    o.noShadow = a.boolean("no_shadow", false);
    a.done();
    noText(e);

    bool pig = false, fin = false, inte = false;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      noText(c);
      if (transformStep(c, o.transforms)) continue;
      if (auto* mesh = std::get_if<MeshDesc>(&o.shape)) {
        if (std::strcmp(c->Name(), "triangle") == 0) {
          Attributes b = attrs(c);
          mesh->triangles.push_back(triangle(b));
          b.done();
          noChildren(c);
          continue;
        }
        if (std::strcmp(c->Name(), "smooth_triangle") == 0) {
          Attributes b = attrs(c);
          mesh->smoothTriangles.push_back(smoothTriangle(b));
          b.done();
          noChildren(c);
          continue;
        }
      }
      if (named && (std::strcmp(c->Name(), "pigment") == 0 || std::strcmp(c->Name(), "finish") == 0 ||
                    std::strcmp(c->Name(), "interior") == 0))
        throw errorAt(c, "the object already uses material '" + (ahead_ ? *use : o.material.name) + "'");
      if (!materialPart(c, o.material, pig, fin, inte))
        throw errorAt(c, "unknown element inside <" + std::string(name) + ">");
    }
    if (const auto* mesh = std::get_if<MeshDesc>(&o.shape)) {
      if (mesh->triangles.empty() && mesh->smoothTriangles.empty())
        throw errorAt(e, "a mesh needs at least one triangle or smooth_triangle");
      // POV-Ray's Parse_Mesh leaves out each triangle whose corners give a cross product of
      // length 0 (Mesh::Degenerate) and refuses a mesh left with none ("No triangles in
      // triangle mesh"): such a mesh's export would not parse.
      const auto flat = [](const Vec3& p1, const Vec3& p2, const Vec3& p3) {
        return length(cross(p1 - p2, p3 - p2)) == 0.0;
      };
      const bool none = std::all_of(mesh->triangles.begin(), mesh->triangles.end(),
                                    [&](const TriangleDesc& t) { return flat(t.p1, t.p2, t.p3); }) &&
                        std::all_of(mesh->smoothTriangles.begin(), mesh->smoothTriangles.end(),
                                    [&](const SmoothTriangleDesc& t) { return flat(t.p1, t.p2, t.p3); });
      if (none)
        throw errorAt(e,
                      "every triangle of the mesh has its corners on a line, so it has none (POV-Ray: \"No "
                      "triangles in triangle mesh\")");
    }
    checkSingular(e, o.transforms);
    return o;
  }

  TriangleDesc triangle(Attributes& a) {
    TriangleDesc t{a.vec("p1"), a.vec("p2"), a.vec("p3"), a.loc()};
    return t;
  }
  SmoothTriangleDesc smoothTriangle(Attributes& a) {
    SmoothTriangleDesc t;
    t.loc = a.loc();
    t.p1 = a.vec("p1");
    t.n1 = a.nonZeroVec("n1");
    t.p2 = a.vec("p2");
    t.n2 = a.nonZeroVec("n2");
    t.p3 = a.vec("p3");
    t.n3 = a.nonZeroVec("n3");
    return t;
  }

  FileName file_;
  bool ahead_ = false;  // Mode::Ahead
  SceneDesc scene_;
  std::unordered_map<std::string, size_t> materialIndex_;  // scene_.materials by name
  // Equal finishes and interiors read by this loader share one copy (core/shared_value.h).
  SharingPool<FinishDesc> finishes_;
  SharingPool<InteriorDesc> interiors_;
  bool haveCamera_ = false, haveGlobals_ = false, haveBackground_ = false;
  int lineOffset_ = 0;  // added to tinyxml2's line numbers: nonzero while reading a piece
  // While a piece is read, its objects go to places_[next_, end_) (see placeIn).
  ObjectDesc* places_ = nullptr;
  size_t next_ = 0, end_ = 0;
  std::vector<Pending> pending_;  // Mode::Ahead: what settle() will do, in file order
  struct Including {
    std::string name, id;  // as messages show it; identity()
  };
  std::vector<Including> including_;  // the file being read, and those including it, outermost first
  size_t includesRead_ = 0, includedBytes_ = 0;  // in all, for kMaxIncludes and kMaxSceneBytes
};

// The file with the root's children replaced by their newlines alone: its declaration,
// comments, root and what follows keep their lines.
std::string skeletonOf(std::string_view bytes, const XmlSplit& split) {
  std::string out(bytes.substr(0, split.bodyBegin));
  out.append(size_t(split.bodyLines), '\n');
  out.append(bytes.substr(split.bodyEnd));
  return out;
}

// Pieces of about `pieceBytes`, or smaller when several threads parse them at once: their
// trees together (tinyxml2's is about four times the text) then take no more memory than
// one piece of `pieceBytes` would, and there are enough of them to share out evenly. With
// 2 * pieceBytes / threads, peak RSS of 10^6 spheres with 16 threads was 1% above that of the
// two-stage pipeline before.
size_t pieceSize(size_t fileBytes, size_t pieceBytes) {
  const size_t threads = size_t(std::max(1, threadBudget()));
  const size_t even = std::min(fileBytes / (8 * threads), pieceBytes / threads);
  return std::min(pieceBytes, std::max(size_t(64) << 10, even));
}

// XML 1.0 (section 2.11): a lone carriage return ends a line, as a line feed does, and CR LF
// is one line end. tinyxml2 counts line feeds only, so in a file with CR line ends every
// message would say line 1: such a file is read with each lone CR as LF (the same length, so
// every offset holds). CR LF needs nothing: its LF is counted once. Empty when no lone CR.
std::string withLineFeeds(std::string_view bytes) {
  // Most files have no lone CR. It is looked for on every thread first (a 243 MB file took
  // one thread some 30 ms), and only a file that has one is copied.
  const Blocks blocks(bytes.size(), 0, size_t(1) << 20);
  std::atomic<bool> lone{false};
  parallelBlocks(blocks, 0, [&](size_t, size_t lo, size_t hi) {
    const std::string_view part = bytes.substr(lo, hi - lo);
    for (size_t i = part.find('\r'); i != std::string_view::npos; i = part.find('\r', i + 1))
      if (lo + i + 1 >= bytes.size() || bytes[lo + i + 1] != '\n') {
        lone = true;
        return;
      }
  });
  if (!lone) return {};
  std::string out;
  for (size_t i = bytes.find('\r'); i != std::string_view::npos; i = bytes.find('\r', i + 1)) {
    if (i + 1 < bytes.size() && bytes[i + 1] == '\n') continue;
    if (out.empty()) out.assign(bytes);
    out[i] = '\n';
  }
  return out;
}

// The scene read a piece at a time (Loader::loadPieces, which `release` is passed to when the
// pieces are `bytes` themselves), or nullopt when the file must be read whole.
std::optional<SceneDesc> parseInPieces(std::string_view bytes, const std::string& name, const LoadOptions& options,
                                       const std::function<void(size_t, size_t)>& release) {
  if (options.piecesRead) *options.piecesRead = 0;
  const std::string lineFeeds = withLineFeeds(bytes);
  if (!lineFeeds.empty()) bytes = lineFeeds;
  if (bytes.size() <= options.pieceBytes) return std::nullopt;
  const std::optional<XmlSplit> split = splitXmlRoot(bytes, pieceSize(bytes.size(), options.pieceBytes), isObjectName);
  // What lies around the pieces (the skeleton) is checked here, the pieces by the loader.
  if (!split || !isSceneText(bytes.substr(0, split->bodyBegin)) || !isSceneText(bytes.substr(split->bodyEnd)))
    return std::nullopt;
  tinyxml2::XMLDocument skeleton;
  const std::string text = skeletonOf(bytes, *split);
  // A closing tag too many after the root is no error to tinyxml2: the whole parse says so.
  if (skeleton.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS || !closesOnlyOpenElements(text))
    return std::nullopt;
  std::optional<SceneDesc> s =
      Loader(name).loadPieces(skeleton, bytes, *split, lineFeeds.empty() ? release : nullptr);
  if (!s) return std::nullopt;
  if (options.piecesRead) *options.piecesRead = split->pieces.size();
  s->path = name;
  return s;
}

SceneDesc parseWhole(std::string_view bytes, const std::string& name) {
  const std::string lineFeeds = withLineFeeds(bytes);
  if (!lineFeeds.empty()) bytes = lineFeeds;
  checkSceneText(bytes, name);
  tinyxml2::XMLDocument doc;
  parseCheckedText(doc, bytes, name);
  SceneDesc s = Loader(name).load(doc);
  s.path = name;
  return s;
}

}  // namespace

SceneDesc loadSceneString(const std::string& xml, const std::string& name, const LoadOptions& options) {
  if (std::optional<SceneDesc> s = parseInPieces(xml, name, options, nullptr)) return std::move(*s);
  return parseWhole(xml, name);
}

SceneDesc loadSceneFile(const std::string& path, const LoadOptions& options) {
  {
    SceneBytes bytes(path);
    // The text of each piece read is given back as soon as it is read, so that a big file's
    // text and its objects are not held whole at once; if the pieces' way then gives up, the
    // file is read again for the whole parse.
    std::atomic<bool> released{false};
    const auto release = [&](size_t begin, size_t end) {
      if (bytes.release(begin, end)) released.store(true, std::memory_order_relaxed);
    };
    // A mapped file that changed size while it was read gave zeros or too little: whatever
    // came of that (a scene, an error) is not the file's, which is read again below.
    try {
      if (std::optional<SceneDesc> s = parseInPieces(bytes.view(), path, options, release); s && bytes.intact())
        return std::move(*s);
      if (!released.load() && bytes.intact()) {
        SceneDesc s = parseWhole(bytes.view(), path);
        if (bytes.intact()) return s;
      }
    } catch (...) {
      if (bytes.intact()) throw;
    }
  }
  const SceneBytes read(path, SceneBytes::Way::Read);
  return parseWhole(read.view(), path);
}

}  // namespace pvrt
