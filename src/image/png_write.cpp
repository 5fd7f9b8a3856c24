// Writing PNGs by hand around zlib, so that deflate, the slow part, runs on every thread
// as in pigz: the rows are cut into bands of about kBandBytes, and each band is filtered
// and deflated on its own into a piece of raw deflate data that ends on a byte boundary
// (Z_SYNC_FLUSH; Z_FINISH for the last band). A band's deflate is first given the 32 KiB
// of filtered rows before it as its dictionary, so it finds the matches that one serial
// stream would: paper1 at 1280x800 takes 412,735 bytes (libpng's one stream 413,899;
// bands without the dictionary 1% more). The pieces behind one zlib header, followed by
// the Adler-32 of all the filtered bytes (combined from the bands'), are the image's zlib
// stream; each piece is written as one IDAT chunk. The bands depend only on the image's
// size, so the file is the same bytes whatever the number of threads.
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <new>
#include <stdexcept>

#include "image/png_io.h"
#include "parallel/parallel_for.h"

namespace pvrt {

namespace {

// Filtered bytes per band (whole rows, at least one). Priming a band with 32 KiB costs about
// a fifth of deflating 32 KiB: 64 KiB bands took 8% more CPU time than libpng at 1280x800,
// 128 KiB ones 3% less, and at 16 threads 1280x800 is two rounds of 24 bands.
constexpr size_t kBandBytes = 128 * 1024;
constexpr size_t kWindow = 32 * 1024;  // deflate's window: what a band's dictionary can reach

// Level 3 with every row filtered by its left neighbour (Sub). Against libpng's adaptive
// choice among the five filters at the same level, renders of 1280x800 compress 1.5-2.5
// times as fast (paper1: 0.031 s against 0.047 s) and mostly smaller (paper1 4% smaller,
// paper2 4% larger). Z_FILTERED is what libpng chose for filtered rows (levels 1-3 ignore it).
constexpr int kLevel = 3;
constexpr uint8_t kFilterSub = 1;
// The zlib header zlib itself writes at level 3: deflate with a 32 KiB window, "fast"
// compression, and a check value that makes the pair a multiple of 31.
constexpr uint8_t kZlibHeader[2] = {0x78, 0x5e};

// One band of rows, deflated.
struct Piece {
  std::vector<uint8_t> deflated;  // raw deflate data, ending on a byte boundary
  uLong crc = 0;                  // CRC-32 of `deflated`
  uLong adler = 0;                // Adler-32 of the band's filtered rows
  size_t filteredSize = 0;
  std::string error;
};

void filterRowSub(const uint8_t* row, size_t rowBytes, uint8_t* out) {
  out[0] = kFilterSub;
  const size_t first = std::min<size_t>(3, rowBytes);  // the first pixel has no left neighbour
  std::memcpy(out + 1, row, first);
  for (size_t i = first; i < rowBytes; ++i) out[1 + i] = uint8_t(row[i] - row[i - 3]);
}

// Appends the deflate of [in, in + size) to `out`, finishing as `flush` asks.
bool deflateInto(z_stream& z, const uint8_t* in, size_t size, int flush, std::vector<uint8_t>& out) {
  z.next_in = const_cast<uint8_t*>(in);
  size_t left = size;
  do {  // avail_in is 32-bit: feed at most 1 GiB a call
    z.avail_in = uInt(std::min<size_t>(left, size_t(1) << 30));
    left -= z.avail_in;
    const int mode = left > 0 ? Z_NO_FLUSH : flush;
    do {  // until deflate leaves room unused: all input taken, and flushed as asked
      if (out.size() - z.total_out < 64) out.resize(out.size() + out.size() / 2 + 64);
      z.next_out = out.data() + z.total_out;
      z.avail_out = uInt(std::min<size_t>(out.size() - z.total_out, size_t(1) << 30));
      const int rc = deflate(&z, mode);
      if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR) return false;
    } while (z.avail_out == 0);
  } while (left > 0);
  out.resize(z.total_out);
  return true;
}

// A raw deflate stream, ended however deflateBand leaves it (deflateEnd is harmless on a
// stream whose initialisation failed).
struct Deflater {
  z_stream z{};
  ~Deflater() { deflateEnd(&z); }
};

Piece deflateBand(const uint8_t* rgb, int width, int y0, int y1, bool last) {
  Piece piece;
  const size_t rowBytes = size_t(width) * 3, stride = rowBytes + 1;
  // The rows before the band that fill the dictionary, filtered again here.
  const int primeRows = int(std::min<size_t>(size_t(y0), (kWindow + stride - 1) / stride));
  std::vector<uint8_t> filtered(size_t(y1 - y0 + primeRows) * stride);
  for (int y = y0 - primeRows; y < y1; ++y)
    filterRowSub(rgb + size_t(y) * rowBytes, rowBytes, filtered.data() + size_t(y - y0 + primeRows) * stride);
  const uint8_t* band = filtered.data() + size_t(primeRows) * stride;
  piece.filteredSize = size_t(y1 - y0) * stride;
  piece.adler = adler32_z(adler32_z(0, nullptr, 0), band, piece.filteredSize);

  Deflater d;
  if (deflateInit2(&d.z, kLevel, Z_DEFLATED, -15, 8, Z_FILTERED) != Z_OK) {
    piece.error = "out of memory";
    return piece;
  }
  const size_t dictionary = std::min(size_t(primeRows) * stride, kWindow);
  piece.deflated.resize(deflateBound(&d.z, uLong(piece.filteredSize)) + 16);
  if ((dictionary > 0 && deflateSetDictionary(&d.z, band - dictionary, uInt(dictionary)) != Z_OK) ||
      !deflateInto(d.z, band, piece.filteredSize, last ? Z_FINISH : Z_SYNC_FLUSH, piece.deflated))
    piece.error = "deflate failed";
  piece.crc = crc32_z(crc32_z(0, nullptr, 0), piece.deflated.data(), piece.deflated.size());
  return piece;
}

void putBigEndian(uint8_t* p, uint32_t v) {
  p[0] = uint8_t(v >> 24);
  p[1] = uint8_t(v >> 16);
  p[2] = uint8_t(v >> 8);
  p[3] = uint8_t(v);
}

// Part of a chunk's data, with the CRC-32 of its bytes alone.
struct Part {
  const uint8_t* data;
  size_t size;
  uLong crc;
};
Part part(const void* data, size_t size) {
  const auto* bytes = static_cast<const uint8_t*>(data);
  return {bytes, size, crc32_z(crc32_z(0, nullptr, 0), bytes, size)};
}

// One chunk: length, type, the parts' bytes, and the CRC-32 of type and data (combined from
// the parts' own, so that the big ones were computed on the threads that made them).
bool writeChunk(std::FILE* f, const char* type, std::initializer_list<Part> parts) {
  size_t length = 0;
  uLong crc = crc32_z(crc32_z(0, nullptr, 0), reinterpret_cast<const uint8_t*>(type), 4);
  for (const Part& p : parts) {
    length += p.size;
    crc = crc32_combine(crc, p.crc, z_off_t(p.size));
  }
  uint8_t head[8], tail[4];
  putBigEndian(head, uint32_t(length));
  std::memcpy(head + 4, type, 4);
  putBigEndian(tail, uint32_t(crc));
  bool ok = std::fwrite(head, 1, 8, f) == 8;
  for (const Part& p : parts) ok = ok && std::fwrite(p.data, 1, p.size, f) == p.size;
  return ok && std::fwrite(tail, 1, 4, f) == 4;
}

// The chunks libpng wrote before the image data: 8-bit RGB, the sRGB chunk telling viewers
// the values are already display-encoded (with the gAMA and cHRM that readers without sRGB
// support use instead), and the program's name.
bool writeHeader(std::FILE* f, int width, int height) {
  static const uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  uint8_t ihdr[13] = {0, 0, 0, 0, 0, 0, 0, 0, 8, 2, 0, 0, 0};  // 8 bits, RGB, deflate, filters, no interlace
  putBigEndian(ihdr, uint32_t(width));
  putBigEndian(ihdr + 4, uint32_t(height));
  uint8_t gama[4], chrm[32];
  putBigEndian(gama, 45455);  // 1/2.2 times 100000
  const uint32_t whiteAndPrimaries[8] = {31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000};
  for (int i = 0; i < 8; ++i) putBigEndian(chrm + 4 * i, whiteAndPrimaries[i]);
  const uint8_t srgb = 0;  // perceptual rendering intent
  static const char software[] = "Software\0pvrt";
  return std::fwrite(signature, 1, 8, f) == 8 && writeChunk(f, "IHDR", {part(ihdr, 13)}) &&
         writeChunk(f, "gAMA", {part(gama, 4)}) && writeChunk(f, "sRGB", {part(&srgb, 1)}) &&
         writeChunk(f, "cHRM", {part(chrm, 32)}) && writeChunk(f, "tEXt", {part(software, sizeof software - 1)});
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

std::string writePng8(const std::string& path, int width, int height, const uint8_t* rgb, int threads) {
  if (width <= 0 || height <= 0) return "a PNG needs at least one pixel";
  const size_t stride = size_t(width) * 3 + 1;
  const int bandRows = int(std::clamp<size_t>(kBandBytes / stride, 1, size_t(height)));
  const size_t bands = size_t((height + bandRows - 1) / bandRows);
  std::vector<Piece> pieces(bands);
  parallelIndices(bands, threads, [&](size_t b) {
    const int y0 = int(b) * bandRows, y1 = std::min(height, y0 + bandRows);
    try {
      pieces[b] = deflateBand(rgb, width, y0, y1, b + 1 == bands);
    } catch (const std::bad_alloc&) {
      pieces[b].error = "out of memory";
    } catch (const std::exception& e) {
      pieces[b].error = e.what();
    }
  });
  uLong adler = adler32_z(0, nullptr, 0);
  for (const Piece& p : pieces) {
    if (!p.error.empty()) return p.error;
    adler = adler32_combine(adler, p.adler, z_off_t(p.filteredSize));
  }
  uint8_t trailer[4];
  putBigEndian(trailer, uint32_t(adler));

  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "wb"));
  if (!f) return std::strerror(errno);
  bool ok = writeHeader(f.get(), width, height);
  for (size_t b = 0; b < bands && ok; ++b) {
    const Piece& p = pieces[b];
    ok = writeChunk(f.get(), "IDAT",
                    {part(kZlibHeader, b == 0 ? 2 : 0), {p.deflated.data(), p.deflated.size(), p.crc},
                     part(trailer, b + 1 == bands ? 4 : 0)});
  }
  ok = ok && writeChunk(f.get(), "IEND", {});
  if (!ok || std::fflush(f.get()) != 0 || std::ferror(f.get())) return std::strerror(errno);
  if (std::fclose(f.release()) != 0) return std::strerror(errno);
  return {};
}

}  // namespace pvrt
