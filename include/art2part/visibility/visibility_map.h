// Which triangles are visible along which directions: one bit per (triangle, direction), a row per triangle.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace art2part {

// A dense bit matrix. Row r, column c. Rows are padded to whole 64-bit words; bit c of a row lies in word c / 64 at
// bit c % 64, which on a little-endian machine is byte c / 8, bit c % 8: the visibility.bits layout.
class BitMatrix {
 public:
  BitMatrix() = default;
  BitMatrix(int rows, int columns);

  int rows() const { return rows_; }
  int columns() const { return columns_; }
  int wordsPerRow() const { return words_; }

  bool get(int r, int c) const { return (data_[index(r, c)] >> (c & 63)) & 1u; }
  void set(int r, int c) { data_[index(r, c)] |= std::uint64_t(1) << (c & 63); }
  void reset(int r, int c) { data_[index(r, c)] &= ~(std::uint64_t(1) << (c & 63)); }
  std::uint64_t* row(int r) { return data_.data() + static_cast<std::size_t>(r) * words_; }
  const std::uint64_t* row(int r) const { return data_.data() + static_cast<std::size_t>(r) * words_; }
  int rowCount(int r) const;  // bits set in row r
  BitMatrix transposed() const;
  bool operator==(const BitMatrix& o) const {
    return rows_ == o.rows_ && columns_ == o.columns_ && data_ == o.data_;
  }

 private:
  std::size_t index(int r, int c) const { return static_cast<std::size_t>(r) * words_ + (c >> 6); }
  int rows_ = 0, columns_ = 0, words_ = 0;
  std::vector<std::uint64_t> data_;
};

// bits.get(t, d): triangle t is visible along direction d.
struct VisibilityMap {
  BitMatrix bits;
  int triangles() const { return bits.rows(); }
  int directions() const { return bits.columns(); }
};

// visibility.bits of the file contracts: one row per triangle, ceil(D / 8) bytes, bit d least significant first.
void writeVisibilityBits(const VisibilityMap& map, const std::string& path);
VisibilityMap readVisibilityBits(const std::string& path, int triangles, int directions);

}  // namespace art2part
