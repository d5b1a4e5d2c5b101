#include "maille/detail/structured_grid.hpp"

#include <algorithm>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace maille::detail {

namespace {

int family_of(int di, int dj) {
  for (std::size_t f = 0; f < StructuredGrid::kFamilies.size(); ++f)
    if (StructuredGrid::kFamilies[f][0] == di && StructuredGrid::kFamilies[f][1] == dj)
      return static_cast<int>(f);
  return -1;
}

// Rows per block: at least two (a bend link reaches two rows down, so blocks of one colour,
// two blocks apart, never touch one point), about kBlocks blocks per grid.
std::uint32_t rows_per_block(std::uint32_t ny) {
  return std::max<std::uint32_t>(2, (ny + StructuredGrid::kBlocks - 1) / StructuredGrid::kBlocks);
}

}  // namespace

void StructuredGrid::clear() {
  links_ = 0;
  segments_.clear();
  uniform_.clear();
  blocks_.clear();
  colour_begin_.clear();
  grids_.clear();
  row_base_.clear();
  row_segment_.clear();
  present_.clear();
  width_ = 0;
}

int StructuredGrid::team_size() {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}

int StructuredGrid::thread_index() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

void StructuredGrid::reserve(int threads) const {
  const auto size = [&](int t) { return link_row_size() * (1 + kRowsPerThread * std::size_t(t)); };
  if (threads <= reserved_ && scratch_.size() == size(reserved_)) return;
  reserved_ = std::max(threads, 1);
  scratch_.assign(size(reserved_), Real(0));
}

void StructuredGrid::release_scratch() {
  std::vector<Key>().swap(keys_);
  std::vector<std::uint32_t>().swap(order_);
  std::vector<std::uint32_t>().swap(block_of_);
  std::vector<std::uint32_t>().swap(block_colour_);
}

std::span<const std::uint32_t> StructuredGrid::select(std::span<const LinkEnds> ends,
                                                      std::span<const PointGrid> grids,
                                                      std::vector<std::uint32_t>& others) {
  clear();
  others.clear();
  keys_.clear();
  order_.clear();
  block_of_.clear();
  block_colour_.clear();
  // Grids by first point; one that overlaps the one before is left out (its links could then
  // touch a point of a block running at the same time).
  std::vector<PointGrid> sorted;
  for (const PointGrid& g : grids)
    if (g.nx >= 2 && g.ny >= 2) sorted.push_back(g);
  std::sort(sorted.begin(), sorted.end(),
            [](const PointGrid& p, const PointGrid& q) { return p.first < q.first; });
  std::vector<std::uint32_t> block_base;  // first global block of each kept grid
  std::vector<PointGrid> kept;
  for (const PointGrid& g : sorted) {
    if (!kept.empty() &&
        std::uint64_t(kept.back().first) + kept.back().nx * kept.back().ny > g.first)
      continue;
    block_base.push_back(static_cast<std::uint32_t>(block_colour_.size()));
    kept.push_back(g);
    row_base_.push_back(kept.size() == 1 ? 0 : row_base_.back() + kept[kept.size() - 2].ny);
    width_ = std::max<std::size_t>(width_, std::size_t(g.nx) + 4);
    const std::uint32_t blocks = (g.ny + rows_per_block(g.ny) - 1) / rows_per_block(g.ny);
    for (std::uint32_t k = 0; k < blocks; ++k) block_colour_.push_back(k % 2);
  }
  for (std::uint32_t l = 0; l < ends.size(); ++l) {
    const std::uint32_t a = ends[l].a, b = ends[l].b;
    const auto it =
        std::upper_bound(kept.begin(), kept.end(), a,
                         [](std::uint32_t p, const PointGrid& g) { return p < g.first; });
    int family = -1;
    std::uint32_t g = 0, ia = 0, ja = 0;
    if (it != kept.begin()) {
      const PointGrid& grid = *(it - 1);
      g = static_cast<std::uint32_t>(it - 1 - kept.begin());
      const std::uint64_t end = std::uint64_t(grid.first) + std::uint64_t(grid.nx) * grid.ny;
      if (a < end && b >= grid.first && b < end) {
        ia = (a - grid.first) % grid.nx, ja = (a - grid.first) / grid.nx;
        const std::uint32_t ib = (b - grid.first) % grid.nx, jb = (b - grid.first) / grid.nx;
        family = family_of(int(ib) - int(ia), int(jb) - int(ja));
      }
    }
    if (family < 0) {
      others.push_back(l);
      continue;
    }
    const std::uint32_t block = block_base[g] + ja / rows_per_block(kept[g].ny);
    keys_.push_back({g, block, ja, std::uint32_t(family), ia, l});
  }
  std::sort(keys_.begin(), keys_.end(),
            [](const Key& p, const Key& q) { return p.tuple() < q.tuple(); });
  // A second link with the same ends and family (a duplicate) runs through the general path.
  std::size_t kept_keys = 0;
  for (std::size_t k = 0; k < keys_.size(); ++k) {
    const Key& key = keys_[k];
    if (kept_keys > 0) {
      const Key& last = keys_[kept_keys - 1];
      if (last.grid == key.grid && last.row == key.row && last.family == key.family &&
          last.column == key.column) {
        others.push_back(key.position);
        continue;
      }
    }
    keys_[kept_keys++] = key;
  }
  keys_.resize(kept_keys);
  std::sort(others.begin(), others.end());
  for (const Key& key : keys_) {
    order_.push_back(key.position);
    block_of_.push_back(key.block);
  }
  links_ = order_.size();
  grids_ = std::move(kept);
  reserved_ = 0;  // the row width may have changed
  return order_;
}

// Segments: links of one block, row and family whose ends both advance by one. Blocks: the
// segments of each block, even blocks first.
void StructuredGrid::cut_segments(std::span<const LinkEnds> ends) {
  std::vector<Block> by_block(block_colour_.size(), Block{0, 0});
  for (std::uint32_t s = 0; s < links_; ++s) {
    const bool continues = s > 0 && block_of_[s] == block_of_[s - 1] &&
                           keys_[s].row == keys_[s - 1].row &&
                           keys_[s].family == keys_[s - 1].family &&
                           ends[s].a == ends[s - 1].a + 1 && ends[s].b == ends[s - 1].b + 1;
    if (continues) {
      ++segments_.back().count;
    } else {
      segments_.push_back({ends[s].a, ends[s].b, s, 1});
      Block& b = by_block[block_of_[s]];
      if (b.begin == b.end) b.begin = static_cast<std::uint32_t>(segments_.size() - 1);
    }
    by_block[block_of_[s]].end = static_cast<std::uint32_t>(segments_.size());
  }
  // Segments by grid row and family (they are stored in that order).
  const std::size_t families = kFamilies.size();
  const std::size_t rows = grids_.empty() ? 0 : row_base_.back() + grids_.back().ny;
  row_segment_.assign(rows * families + 1, 0);
  for (const Segment& segment : segments_) {
    const Key& key = keys_[segment.slot];  // keys_ are in storage order
    ++row_segment_[(row_base_[key.grid] + key.row) * families + key.family + 1];
  }
  for (std::size_t r = 0; r + 1 < row_segment_.size(); ++r) row_segment_[r + 1] += row_segment_[r];
  present_.assign(grids_.size(), 0);
  for (const Segment& segment : segments_) {
    const Key& key = keys_[segment.slot];
    present_[key.grid] = std::uint8_t(present_[key.grid] | (1u << key.family));
  }
  // The kernel no longer writes an absent family's row buffers, which the six-family sum reads:
  // they must hold zeros, not a former structure's forces.
  std::fill(scratch_.begin(), scratch_.end(), Real(0));
  colour_begin_.assign(1, 0);
  for (std::uint32_t colour = 0; colour < 2; ++colour) {
    for (std::size_t k = 0; k < by_block.size(); ++k)
      if (block_colour_[k] == colour && by_block[k].end > by_block[k].begin)
        blocks_.push_back(by_block[k]);
    colour_begin_.push_back(static_cast<std::uint32_t>(blocks_.size()));
  }
}

void StructuredGrid::edited(std::uint32_t slot) {
  if (slot >= links_) return;
  const auto it = std::upper_bound(segments_.begin(), segments_.end(), slot,
                                   [](std::uint32_t s, const Segment& g) { return s < g.slot; });
  uniform_[static_cast<std::size_t>(it - 1 - segments_.begin())] = 0;
}

}  // namespace maille::detail
