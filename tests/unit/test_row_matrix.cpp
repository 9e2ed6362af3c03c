// RowMatrix: rows of one width in one block, read as spans.
#include "kernel/core/row_matrix.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <vector>

using thermnet::RowMatrix;

TEST_CASE("row matrix: push_back sets the width, rows read back as written") {
  RowMatrix m;
  CHECK(m.empty());
  m.push_back(std::vector<double>{1, 2, 3});
  m.push_back(std::vector<double>{4, 5, 6});
  REQUIRE(m.size() == 2);
  CHECK(m.cols() == 3);
  CHECK(m[1][2] == 6);
  CHECK(m.front()[0] == 1);
  CHECK(m.back()[1] == 5);
  CHECK(m.at(1, 0) == 4);
  CHECK_THROWS_AS(m.at(2, 0), std::out_of_range);
  CHECK_THROWS_AS(m.at(0, 3), std::out_of_range);
  CHECK_THROWS_AS(m.push_back(std::vector<double>{7, 8}), std::invalid_argument);
  CHECK(m.size() == 2); // the refused row left nothing behind
  m[0][1] = 20;
  CHECK(m.values() == std::vector<double>{1, 20, 3, 4, 5, 6});
}

TEST_CASE("row matrix: iteration visits every row, also rows of width 0") {
  RowMatrix m(4, 2, 1.5);
  double sum = 0;
  std::size_t rows = 0;
  for (auto row : m) {
    ++rows;
    for (double v : row)
      sum += v;
  }
  CHECK(rows == 4);
  CHECK(sum == doctest::Approx(12.0));
  CHECK(std::distance(m.begin(), m.end()) == 4);
  RowMatrix empty_rows(3, 0);
  CHECK(std::distance(empty_rows.begin(), empty_rows.end()) == 3);
  const RowMatrix& c = m;
  CHECK(std::all_of(c.begin(), c.end(), [](auto row) { return row.size() == 2; }));
  RowMatrix other(4, 2, 1.5);
  CHECK(m == other);
  other[3][1] = 0;
  CHECK_FALSE(m == other);
  m.clear();
  CHECK(m.empty());
  m.push_back(std::vector<double>{9}); // the width is set again
  CHECK(m.cols() == 1);
}
