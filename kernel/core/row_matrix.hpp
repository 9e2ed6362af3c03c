#pragma once
/// A table of rows of equal length kept in one block (row k, column i): a time series of node
/// temperatures or flows without a heap block per row (10^6 rows of three doubles take 24 MB, not
/// the 72 MB of a vector of vectors).

#include <cstddef>
#include <iterator>
#include <span>
#include <stdexcept>
#include <vector>

namespace thermnet {

/// Rows of `cols()` doubles in one contiguous block; row k is a span.
class RowMatrix {
public:
  /// Iterator over the rows (each a span of the row's values).
  template <class Value> class RowIterator {
  public:
    using iterator_category = std::random_access_iterator_tag; ///< random access over rows
    using value_type = std::span<Value>;                       ///< one row
    using difference_type = std::ptrdiff_t;                    ///< distance in rows
    using reference = std::span<Value>;                        ///< rows are returned by value
    using pointer = void;                                      ///< no row object to point at
    RowIterator() = default;
    /// Iterator at row `k` of rows of `cols` values starting at `data`.
    RowIterator(Value* data, std::size_t cols, std::ptrdiff_t k)
        : data_(data), cols_(cols), k_(k) {}
    /// The row it points at.
    std::span<Value> operator*() const {
      return {data_ + static_cast<std::size_t>(k_) * cols_, cols_};
    }
    /// Row `n` further on.
    std::span<Value> operator[](difference_type n) const { return *(*this + n); }
    /// Next row.
    RowIterator& operator++() {
      ++k_;
      return *this;
    }
    /// Next row (postfix).
    RowIterator operator++(int) {
      RowIterator was = *this;
      ++k_;
      return was;
    }
    /// Previous row.
    RowIterator& operator--() {
      --k_;
      return *this;
    }
    /// Previous row (postfix).
    RowIterator operator--(int) {
      RowIterator was = *this;
      --k_;
      return was;
    }
    /// Moves by `n` rows.
    RowIterator& operator+=(difference_type n) {
      k_ += n;
      return *this;
    }
    /// Moves back by `n` rows.
    RowIterator& operator-=(difference_type n) {
      k_ -= n;
      return *this;
    }
    /// `n` rows further on.
    friend RowIterator operator+(RowIterator it, difference_type n) { return it += n; }
    /// `n` rows further on.
    friend RowIterator operator+(difference_type n, RowIterator it) { return it += n; }
    /// `n` rows back.
    friend RowIterator operator-(RowIterator it, difference_type n) { return it -= n; }
    /// Rows between two iterators of one matrix.
    friend difference_type operator-(const RowIterator& a, const RowIterator& b) {
      return a.k_ - b.k_;
    }
    /// Same row.
    friend bool operator==(const RowIterator& a, const RowIterator& b) { return a.k_ == b.k_; }
    /// Order of rows.
    friend auto operator<=>(const RowIterator& a, const RowIterator& b) { return a.k_ <=> b.k_; }

  private:
    Value* data_ = nullptr;
    std::size_t cols_ = 0;
    std::ptrdiff_t k_ = 0;
  };
  using iterator = RowIterator<double>;             ///< iterator over mutable rows
  using const_iterator = RowIterator<const double>; ///< iterator over read-only rows

  RowMatrix() = default;
  /// `rows` rows of `cols` values, each `value`.
  RowMatrix(std::size_t rows, std::size_t cols, double value = 0.0)
      : cols_(cols), rows_(rows), data_(rows * cols, value) {}

  /// Number of rows.
  std::size_t size() const { return rows_; }
  /// True when there is no row.
  bool empty() const { return rows_ == 0; }
  /// Number of values in each row.
  std::size_t cols() const { return cols_; }
  /// Row k (unchecked).
  std::span<double> operator[](std::size_t k) { return {data_.data() + k * cols_, cols_}; }
  /// Row k (unchecked).
  std::span<const double> operator[](std::size_t k) const {
    return {data_.data() + k * cols_, cols_};
  }
  /// Value i of row k; throws std::out_of_range outside the table.
  double at(std::size_t k, std::size_t i) const {
    if (k >= rows_ || i >= cols_) throw std::out_of_range("RowMatrix: value out of range");
    return data_[k * cols_ + i];
  }
  /// The first row.
  std::span<double> front() { return (*this)[0]; }
  /// The first row.
  std::span<const double> front() const { return (*this)[0]; }
  /// The last row.
  std::span<double> back() { return (*this)[rows_ - 1]; }
  /// The last row.
  std::span<const double> back() const { return (*this)[rows_ - 1]; }
  /// Appends a row; the first row sets the width, a later one of another width throws
  /// std::invalid_argument.
  void push_back(std::span<const double> row) {
    if (rows_ == 0) cols_ = row.size();
    if (row.size() != cols_) throw std::invalid_argument("RowMatrix: row of another width");
    data_.insert(data_.end(), row.begin(), row.end());
    ++rows_;
  }
  /// Room for `rows` rows of `cols` values without reallocating.
  void reserve(std::size_t rows, std::size_t cols) { data_.reserve(rows * cols); }
  /// Makes it `rows` rows of `cols` values, each `value`.
  void assign(std::size_t rows, std::size_t cols, double value) {
    cols_ = cols;
    rows_ = rows;
    data_.assign(rows * cols, value);
  }
  /// Removes every row (the width is set again by the next push_back).
  void clear() {
    rows_ = 0;
    cols_ = 0;
    data_.clear();
  }
  /// First row.
  iterator begin() { return {data_.data(), cols_, 0}; }
  /// Past the last row.
  iterator end() { return {data_.data(), cols_, static_cast<std::ptrdiff_t>(rows_)}; }
  /// First row.
  const_iterator begin() const { return {data_.data(), cols_, 0}; }
  /// Past the last row.
  const_iterator end() const { return {data_.data(), cols_, static_cast<std::ptrdiff_t>(rows_)}; }
  /// Every value, row after row.
  const std::vector<double>& values() const { return data_; }
  /// Same rows and values.
  friend bool operator==(const RowMatrix& a, const RowMatrix& b) {
    return a.rows_ == b.rows_ && a.cols_ == b.cols_ && a.data_ == b.data_;
  }

private:
  std::size_t cols_ = 0;
  std::size_t rows_ = 0;
  std::vector<double> data_;
};

} // namespace thermnet
