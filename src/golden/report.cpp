#include "golden/report.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include <fmt/core.h>

#include "core/error.h"
#include "core/output_files.h"
#include "image/image_io.h"
#include "image/png_io.h"

namespace pvrt::golden {

namespace {

struct Picture {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  bool ok() const { return width > 0; }
};

Picture readPicture(const std::string& path) {
  Picture p;
  if (path.empty()) return p;
  try {
    p.rgb = readImage8(path, p.width, p.height);
  } catch (const Error&) {
    p = {};
  }
  return p;
}

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default:
        // XML 1.0 forbids most control characters even escaped; a log may hold them.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') out += '?';
        else out += c;
    }
  }
  return out;
}

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 | uint8_t(bytes[i + 2]);
    for (int k = 18; k >= 0; k -= 6) out += table[(v >> k) & 63];
  }
  if (i < bytes.size()) {
    uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// PNG bytes as a data URI, through a scratch file (the PNG writer writes files).
std::string dataUri(const Picture& p, const std::string& scratch) {
  if (!p.ok()) return "";
  const std::string why = writePng8(scratch, p.width, p.height, p.rgb.data(), 1);
  if (!why.empty()) throw Error(ExitCode::OutputError, "cannot write \"" + printableName(scratch) + "\": " + why);
  std::ifstream in(scratch, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::remove(scratch.c_str());
  return "data:image/png;base64," + base64(bytes);
}

Picture difference(const Picture& a, const Picture& b, int scale) {
  Picture d = a;
  for (size_t i = 0; i < d.rgb.size(); ++i) d.rgb[i] = uint8_t(std::min(255, std::abs(int(a.rgb[i]) - int(b.rgb[i])) * scale));
  return d;
}

Picture crop(const Picture& p, int x0, int y0, int size) {
  Picture c;
  c.width = std::min(size, p.width);
  c.height = std::min(size, p.height);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      for (int k = 0; k < 3; ++k) c.rgb.push_back(p.rgb[(size_t(y0 + y) * size_t(p.width) + size_t(x0 + x)) * 3 + size_t(k)]);
  return c;
}

// Each distinct picture is embedded once and the <img> elements name it by number: the
// backends of one scene usually render the same bytes, and every identical test has the same
// black difference, so a report of 200 tests holds about a third of their pictures.
struct Pictures {
  std::vector<std::string> uris;
  std::map<std::string, size_t> index;
  std::string tag(const std::string& uri, const char* cls, const std::string& title = "") {
    auto [it, added] = index.emplace(uri, uris.size());
    if (added) uris.push_back(uri);
    return fmt::format("<img class={} data-i={} title=\"{}\">", cls, it->second, escape(title));
  }
  std::string script() const {
    std::string s = "<script>const P=[";
    for (const std::string& u : uris) s += "\n'" + u + "',";
    return s + "];\ndocument.querySelectorAll('img[data-i]').forEach(e=>e.src=P[e.dataset.i]);\n</script>\n";
  }
};

std::string cell(Pictures& pictures, const std::string& uri, const char* cls, const std::string& title) {
  return uri.empty() ? "<td>&mdash;</td>" : "<td>" + pictures.tag(uri, cls, title) + "</td>";
}

void writeAtomically(const std::string& path, const std::string& text) {
  OutputFiles out;
  out.output(path, "report");
  out.stageBytes(path, text);
  out.commit();
}

const char* kStyle = R"(<style>
body{font-family:sans-serif;margin:1em}table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:3px;vertical-align:top}
th{cursor:pointer;background:#eee}th:hover{background:#ddd}.fail{background:#fdd}.pass{background:#efe}
img{image-rendering:pixelated}img.full{width:240px}img.zoom{width:96px}pre{margin:0;white-space:pre-wrap;max-width:28em;font-size:85%}
</style>)";

// Click a header to sort by it; click again to reverse. Cells sort by data-v when they have one.
const char* kScript = R"(<script>
document.querySelectorAll('th').forEach((th,i)=>th.onclick=()=>{const t=th.closest('table'),b=t.tBodies[0];
const up=th.dataset.up!=='1';th.dataset.up=up?'1':'0';const key=r=>{const c=r.cells[i];const v=c.dataset.v;
return v!==undefined?parseFloat(v):c.textContent};[...b.rows].sort((x,y)=>{const p=key(x),q=key(y);
const s=(typeof p==='number'&&typeof q==='number')?p-q:String(p).localeCompare(String(q));return up?s:-s})
.forEach(r=>b.appendChild(r))});
</script>)";

}  // namespace

void worstWindow(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height, int size,
                 int& x0, int& y0) {
  const int w = std::min(size, width), h = std::min(size, height);
  // Summed-area table of the per-pixel difference (all channels), one row and column of zeros first.
  std::vector<long> sum(size_t(width + 1) * size_t(height + 1), 0);
  auto at = [&](int x, int y) -> long& { return sum[size_t(y) * size_t(width + 1) + size_t(x)]; };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      long d = 0;
      for (int k = 0; k < 3; ++k) {
        const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3 + size_t(k);
        d += std::abs(int(a[i]) - int(b[i]));
      }
      at(x + 1, y + 1) = d + at(x, y + 1) + at(x + 1, y) - at(x, y);
    }
  long best = -1;
  x0 = y0 = 0;
  for (int y = 0; y + h <= height; ++y)
    for (int x = 0; x + w <= width; ++x) {
      const long s = at(x + w, y + h) - at(x, y + h) - at(x + w, y) + at(x, y);
      if (s > best) {
        best = s;
        x0 = x;
        y0 = y;
      }
    }
}

void writeHtmlReport(const std::vector<Outcome>& outcomes, const std::string& path, const ReportOptions& o) {
  const long failures = std::count_if(outcomes.begin(), outcomes.end(), [](const Outcome& x) { return !x.passed; });
  std::ostringstream h;
  h << "<!doctype html><html><head><meta charset=utf-8><title>" << escape(o.title) << "</title>" << kStyle
    << "</head><body>\n";
  h << "<h1>" << escape(o.title) << "</h1>\n";
  h << fmt::format("<p><b>{} tests: {} failed, {} passed.</b> Click a column's header to sort by it.</p>\n",
                   outcomes.size(), failures, long(outcomes.size()) - failures);
  if (!o.hint.empty()) h << "<p>" << escape(o.hint) << "</p>\n";
  h << fmt::format("<table><thead><tr><th>test</th><th>verdict</th><th>max error</th><th>channels &gt; 1 level</th>"
                   "<th>mean error</th><th>PSNR dB</th><th>tolerance</th><th>seconds</th><th>new</th><th>reference</th>"
                   "<th>difference x{}</th><th>worst {}x{}: new | reference | difference</th></tr></thead><tbody>\n",
                   o.diffScale, o.zoomSize, o.zoomSize);
  // Failures first, each group by name: the table opens on what needs looking at.
  std::vector<const Outcome*> order;
  for (const Outcome& x : outcomes) order.push_back(&x);
  std::stable_sort(order.begin(), order.end(), [](const Outcome* a, const Outcome* b) { return !a->passed && b->passed; });
  const std::string scratch = path + ".scratch.png";
  std::map<std::string, std::string> referenceUris;  // each reference encoded once
  Pictures pictures;
  for (const Outcome* x : order) {
    const Picture image = readPicture(x->image), reference = readPicture(x->reference);
    const bool same = image.ok() && reference.ok() && image.width == reference.width && image.height == reference.height;
    if (!referenceUris.count(x->reference)) referenceUris[x->reference] = dataUri(reference, scratch);
    std::string diffUri, zoom = "<td>&mdash;</td>";
    if (same) {
      const Picture diff = difference(image, reference, o.diffScale);
      diffUri = dataUri(diff, scratch);
      int x0 = 0, y0 = 0;
      if (x->stats.over0 > 0) {  // identical pictures have no worst area to show
      worstWindow(image.rgb, reference.rgb, image.width, image.height, o.zoomSize, x0, y0);
      const std::string where = fmt::format("pixels ({}, {}) to ({}, {})", x0, y0, x0 + o.zoomSize - 1, y0 + o.zoomSize - 1);
      zoom = "<td title=\"" + where + "\">";
      for (const Picture* p : {&image, &reference, &diff})
        zoom += pictures.tag(dataUri(crop(*p, x0, y0, o.zoomSize), scratch), "zoom") + " ";
      zoom += "<br>" + where + "</td>";
      }
    }
    const CompareResult& r = x->stats;
    const Tolerance& t = x->tolerance;
    const std::string tolerance = fmt::format("&le; {} levels, &le; {:.4f}% over 1{}{}", t.limits.maxLevels,
                                              t.limits.maxFractionOver1 * 100,
                                              t.limits.maxOffBy1 < 0 ? "" : fmt::format(", &le; {} off by 1", t.limits.maxOffBy1),
                                              t.reason.empty() ? "" : "<br><i>" + escape(t.origin + ": " + t.reason) + "</i>");
    h << fmt::format("<tr class={}><td>{}</td><td data-v={}><b>{}</b><pre>{}</pre></td>", x->passed ? "pass" : "fail",
                     escape(x->name), x->passed ? 1 : 0, x->passed ? "PASS" : "FAIL", escape(x->message));
    if (x->compared && !r.sizeMismatch)
      h << fmt::format("<td data-v={0}>{0} @ ({1}, {2})</td><td data-v={3}>{3} of {4}</td><td data-v={5:.6g}>{5:.4g}</td>"
                       "<td data-v={6}>{7}</td>",
                       r.maxError, r.maxX, r.maxY, r.over1, r.channels, r.meanError, std::isinf(r.psnr) ? 1e9 : r.psnr,
                       std::isinf(r.psnr) ? "&infin;" : fmt::format("{:.2f}", r.psnr));
    else
      h << "<td data-v=1e9>&mdash;</td><td data-v=1e18>&mdash;</td><td data-v=1e9>&mdash;</td><td data-v=-1>&mdash;</td>";
    h << fmt::format("<td>{}</td><td data-v={:.3f}>{:.2f}</td>", tolerance, x->seconds, x->seconds);
    h << cell(pictures, dataUri(image, scratch), "full", x->image)
      << cell(pictures, referenceUris[x->reference], "full", x->reference)
      << cell(pictures, diffUri, "full", "difference") << zoom << "</tr>\n";
  }
  h << "</tbody></table>\n" << pictures.script() << kScript << "</body></html>\n";
  writeAtomically(path, h.str());
}

void writeJunit(const std::vector<Outcome>& outcomes, const std::string& path) {
  const long failures = std::count_if(outcomes.begin(), outcomes.end(), [](const Outcome& x) { return !x.passed; });
  double seconds = 0;
  for (const Outcome& x : outcomes) seconds += x.seconds;
  std::ostringstream j;
  j << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  j << fmt::format("<testsuites tests=\"{0}\" failures=\"{1}\" time=\"{2:.3f}\">\n"
                   "<testsuite name=\"pvrt golden\" tests=\"{0}\" failures=\"{1}\" errors=\"0\" time=\"{2:.3f}\">\n",
                   outcomes.size(), failures, seconds);
  for (const Outcome& x : outcomes) {
    j << fmt::format("<testcase classname=\"golden.{}\" name=\"{}\" time=\"{:.3f}\"", escape(x.scene), escape(x.name),
                     x.seconds);
    if (x.passed) {
      j << fmt::format("><system-out>{}</system-out></testcase>\n", escape(x.message));
    } else {
      const std::string first = x.message.substr(0, x.message.find('\n'));
      j << fmt::format("><failure message=\"{}\">{}</failure></testcase>\n", escape(first), escape(x.message));
    }
  }
  j << "</testsuite>\n</testsuites>\n";
  writeAtomically(path, j.str());
}

}  // namespace pvrt::golden
