// How one link pool runs on CPU threads. Private to the CPU executor: the pools hold the links
// (ends and parameters, in the schedule's order), this decides the order and the grouping, and a
// second executor (the GPU) reads the same pools' arrays with a schedule of its own.
//
// Links are grouped into bands by their first point (about kBands bands over the points' range,
// whatever the thread count), and inside a band always-active kinds are sorted by (b - a, a):
// links of one family (every horizontal link of a grid, say) then follow each other with both
// ends advancing by one point, and such runs are computed with contiguous loads instead of
// gathers. Bands are coloured so that no two bands of one colour share a point: on a grid, a
// band touches only its neighbours, so two colours suffice and a step costs two barriers per pool
// (each barrier is a futex wake-up with OMP_WAIT_POLICY=passive, tens of microseconds on a busy
// machine; colouring small chunks instead gave ~20 colours and made two threads slower than one
// at 128^2). Serial runs use the same order, so every point sums its forces in the same order
// whatever the thread count.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "maille/colouring.hpp"
#include "maille/link_kind.hpp"

namespace maille::detail {

class CpuSchedule {
 public:
  static constexpr std::size_t kChunk = 256;  // links per chunk, at most
  static constexpr std::size_t kMinRun = 8;   // shorter runs are not worth a chunk of their own

  // Step 1: the order the links should be stored in: order[slot] = current position (valid
  // until the next call). `by_reach`: sort by (b - a, a) inside bands (always-active kinds;
  // conditional kinds keep their order inside a band).
  std::span<const std::uint32_t> order(std::span<const LinkEnds> ends, bool by_reach);
  // Step 2, once the pool stored its links in that order: chunks, bands and colours.
  void build(std::span<const LinkEnds> ends, std::uint32_t point_count);
  void clear();
  // The working arrays of order() and build() are kept between calls, so that a pool prepared
  // every step (a stage's contacts) allocates nothing once they have grown; a pool prepared
  // once gives them back.
  void release_scratch();
  bool ready() const { return ready_; }

  std::uint32_t chunk_begin(std::size_t c) const { return chunk_begin_[c]; }
  std::uint32_t chunk_end(std::size_t c) const { return chunk_begin_[c + 1]; }
  bool chunk_is_run(std::size_t c) const { return chunk_is_run_[c] != 0; }

  // Colour by colour, the bands no two of which share a point (src/core/schedule_loops.hpp
  // runs them, the threads of a team splitting each colour's bands).
  std::size_t colours() const { return groups_.empty() ? 0 : groups_.size() - 1; }
  std::span<const std::uint32_t> bands_of_colour(std::size_t c) const {
    return std::span<const std::uint32_t>(band_order_)
        .subspan(groups_[c], groups_[c + 1] - groups_[c]);
  }
  std::uint32_t first_chunk(std::uint32_t band) const { return band_begin_[band]; }
  std::uint32_t end_chunk(std::uint32_t band) const { return band_begin_[band + 1]; }

 private:
  static constexpr std::uint32_t kBands = 16;
  static constexpr std::uint32_t kMinBandPoints = 256;
  std::uint32_t band_of(std::uint32_t a) const { return (a - band_origin_) / band_points_; }
  void cut_chunks(std::span<const LinkEnds> ends);

  bool ready_ = false;
  std::uint32_t band_origin_ = 0, band_points_ = 1;  // band of point a: (a - origin) / points
  std::vector<std::uint32_t> chunk_begin_;           // chunk c spans links [begin[c], begin[c+1])
  std::vector<std::uint8_t> chunk_is_run_;           // chunk c is a run: a and b advance by one
  std::vector<std::uint32_t> band_begin_;            // band b spans chunks [begin[b], begin[b+1])
  std::vector<std::uint32_t> band_order_;            // bands grouped by colour
  std::vector<std::uint32_t> groups_;  // colour c spans band_order_[groups_[c]..[c+1])
  // Scratch (see release_scratch): the order, runs, each band's points, the colouring.
  std::vector<std::uint32_t> order_, run_, offsets_, idx_;
  Colouring colouring_;
  ColouringScratch colour_scratch_;
};

}  // namespace maille::detail
