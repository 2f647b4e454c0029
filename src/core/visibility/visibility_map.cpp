#include "art2part/visibility/visibility_map.h"

#include <fstream>
#include <stdexcept>

#include "art2part/geometry/mesh.h"

namespace art2part {

namespace {

int bytesPerRow(int columns) { return (columns + 7) / 8; }

// Byte b of a row: bits 8b .. 8b+7, least significant first. Shifting out of the word rather than reinterpreting
// memory keeps the file layout independent of the machine's byte order.
unsigned char rowByte(const std::uint64_t* row, int b) {
  return static_cast<unsigned char>(row[b / 8] >> (8 * (b % 8)));
}

void setRowByte(std::uint64_t* row, int b, unsigned char value) {
  row[b / 8] |= std::uint64_t(value) << (8 * (b % 8));
}

}  // namespace

BitMatrix::BitMatrix(int rows, int columns) {
  if (rows < 0 || columns < 0) throw std::invalid_argument("BitMatrix: negative size");
  rows_ = rows;
  columns_ = columns;
  words_ = (columns + 63) / 64;
  data_.assign(static_cast<std::size_t>(rows_) * words_, 0);
}

int BitMatrix::rowCount(int r) const {
  int count = 0;
  const std::uint64_t* words = row(r);
  for (int w = 0; w < words_; ++w) count += __builtin_popcountll(words[w]);
  return count;
}

BitMatrix BitMatrix::transposed() const {
  BitMatrix out(columns_, rows_);
  // Walking the set bits of each word keeps this proportional to the bits set, which is what a sparse
  // visibility matrix needs.
  for (int r = 0; r < rows_; ++r) {
    const std::uint64_t* words = row(r);
    for (int w = 0; w < words_; ++w)
      for (std::uint64_t bits = words[w]; bits != 0; bits &= bits - 1)
        out.set(w * 64 + __builtin_ctzll(bits), r);
  }
  return out;
}

void writeVisibilityBits(const VisibilityMap& map, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + path);
  const int bytes = bytesPerRow(map.directions());
  std::vector<char> buffer(bytes);
  for (int t = 0; t < map.triangles(); ++t) {
    const std::uint64_t* row = map.bits.row(t);
    for (int b = 0; b < bytes; ++b) buffer[b] = static_cast<char>(rowByte(row, b));
    out.write(buffer.data(), bytes);
  }
  if (!out) throw std::runtime_error("error writing " + path);
}

VisibilityMap readVisibilityBits(const std::string& path, int triangles, int directions) {
  if (triangles < 0 || directions < 0) throw InputError(path + ": negative size requested");
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError("cannot read " + path);
  const long long bytes = bytesPerRow(directions);
  const long long expected = bytes * triangles;
  const long long actual = static_cast<long long>(in.tellg());
  if (actual != expected)
    throw InputError(path + ": " + std::to_string(actual) + " bytes, expected " + std::to_string(expected) + " for " +
                     std::to_string(triangles) + " triangles x " + std::to_string(directions) + " directions");
  in.seekg(0);
  VisibilityMap map{BitMatrix(triangles, directions)};
  std::vector<char> buffer(bytes);
  for (int t = 0; t < triangles; ++t) {
    if (!in.read(buffer.data(), bytes)) throw InputError("error reading " + path);
    std::uint64_t* row = map.bits.row(t);
    for (int b = 0; b < bytes; ++b) setRowByte(row, b, static_cast<unsigned char>(buffer[b]));
    // Padding bits past the last direction would make equal maps compare unequal and counts wrong.
    if (directions % 64 != 0 && bytes > 0)
      row[map.bits.wordsPerRow() - 1] &= (std::uint64_t(1) << (directions % 64)) - 1;
  }
  return map;
}

}  // namespace art2part
