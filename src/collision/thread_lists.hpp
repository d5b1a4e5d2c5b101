// Per-thread lists of a pass whose work OpenMP hands out by a dynamic schedule (broad-phase
// sinks, triangle candidates and contacts, a facet obstacle's nearby facets). Which thread
// takes which work depends on timing, so on the load on the machine: a thread the OS holds
// back takes none, the other takes it all. A list sized only by what its own thread met so far
// then grows in a step long after the first ones: an allocation in the step, on a loaded
// machine only (physics.Allocation.NoneWhenOneThreadFindsEveryContact). After each pass, the
// helpers below give every list the room that any split of the same work needs, so a later
// pass allocates only when the work itself outgrows every earlier pass, as on one thread.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace maille::collision {

// Before a pass: one empty list per thread (at least one) and no thread full yet (`full`, one
// flag per list); returns each list's cap, its share of `max_entries` (the memory budget).
template <class List>
std::size_t start_lists(std::vector<List>& lists, std::vector<std::uint8_t>& full, int threads,
                        std::size_t max_entries) {
  lists.resize(std::size_t(std::max(threads, 1)));
  for (auto& l : lists) l.clear();
  full.assign(lists.size(), 0);
  return max_entries / lists.size();
}

// Output lists: room in each for everything all of them hold now (one thread may find it all
// next time), rounded up to a power of two as a growing vector would be, and at most `cap`
// entries (each list's share of the memory budget: beyond it the pass is refused anyway).
// `list` projects an element of `lists` on its std::vector (&Sink::pairs).
template <class Lists, class Project = std::identity>
void room_for_any_split(Lists& lists, std::size_t cap, Project list = {}) {
  std::size_t total = 0;
  for (auto& l : lists) total += std::invoke(list, l).size();
  if (total == 0) return;
  const std::size_t want = std::min(std::bit_ceil(total), cap);
  for (auto& l : lists)
    if (std::invoke(list, l).capacity() < want) std::invoke(list, l).reserve(want);
}

// Scratch lists, cleared for each item of the work: room in each for the largest any thread
// has needed (whichever thread meets that item next time).
template <class Lists>
void room_for_any_item(Lists& lists) {
  std::size_t most = 0;
  for (const auto& l : lists) most = std::max(most, l.capacity());
  for (auto& l : lists)
    if (l.capacity() < most) l.reserve(most);
}

}  // namespace maille::collision
