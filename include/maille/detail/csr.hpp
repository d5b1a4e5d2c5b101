// Compressed rows (CSR): the entries of row r are values[row[r]] .. values[row[r + 1] - 1]. The
// engine groups many things this way (a point's links, faces, contact candidates, partners; a
// cell's particles; a colour's points), always by the same counting sort, written once here.
#pragma once

#include <bit>
#include <cstddef>
#include <vector>

namespace maille::detail {

// Room for n, grown to a power of two as a growing vector would (an assign or resize of a
// cleared vector reserves the exact size): rows a little longer at the next step (the cloth
// moving) then need no allocation.
template <class V>
void reserve_pow2(V& v, std::size_t n) {
  if (v.capacity() < n) v.reserve(std::bit_ceil(n));
}

// Fills `row` (rows + 1 offsets) and `values` from a visit of the entries: `each(emit)` calls
// emit(r, value) once per entry (r < rows) and must visit the same entries in the same order
// when called again (it is called twice: to count, then to place); each row keeps its entries
// in visit order. The vectors grow to powers of two and keep their capacity: rows built again
// each step allocate nothing once they are about as large as they get.
template <class Index, class Value, class Each>
void build_rows(std::size_t rows, std::vector<Index>& row, std::vector<Value>& values,
                Each&& each) {
  reserve_pow2(row, rows + 1);
  row.assign(rows + 1, Index(0));
  each([&](std::size_t r, const auto&) { ++row[r + 1]; });
  for (std::size_t r = 0; r < rows; ++r) row[r + 1] += row[r];
  reserve_pow2(values, std::size_t(row[rows]));
  values.resize(std::size_t(row[rows]));
  // Each row's offset serves as its cursor, then the offsets are shifted back one row.
  each([&](std::size_t r, const auto& value) { values[std::size_t(row[r]++)] = Value(value); });
  for (std::size_t r = rows; r > 0; --r) row[r] = row[r - 1];
  row[0] = Index(0);
}

// Rows of the undirected graph of edges (a, b) over `rows` nodes: `each(emit)` calls emit(a, b)
// once per edge; b lands in a's row and a in b's (an edge (a, a) twice in a's).
template <class Index, class Each>
void build_neighbour_rows(std::size_t rows, std::vector<Index>& row, std::vector<Index>& values,
                          Each&& each) {
  build_rows(rows, row, values, [&](auto&& emit) {
    each([&](std::size_t a, std::size_t b) {
      emit(a, Index(b));
      emit(b, Index(a));
    });
  });
}

}  // namespace maille::detail
