#include "maille/link_set.hpp"

namespace maille {

LinkSet::LinkSet(const LinkSet& other) {
  for (const auto& p : other.pools_) pools_.push_back(p->clone());
}

LinkSet& LinkSet::operator=(const LinkSet& other) {
  if (this != &other) *this = LinkSet(other);
  return *this;
}

LinkPoolBase* LinkSet::find(std::string_view keyword) {
  for (auto& p : pools_)
    if (p->keyword() == keyword) return p.get();
  return nullptr;
}

const LinkPoolBase* LinkSet::find(std::string_view keyword) const {
  for (const auto& p : pools_)
    if (p->keyword() == keyword) return p.get();
  return nullptr;
}

LinkPoolBase& LinkSet::adopt(std::unique_ptr<LinkPoolBase> pool) {
  if (LinkPoolBase* existing = find(pool->keyword())) return *existing;
  pools_.push_back(std::move(pool));
  return *pools_.back();
}

std::size_t LinkSet::total() const {
  std::size_t n = 0;
  for (const auto& p : pools_) n += p->size();
  return n;
}

void LinkSet::prepare(std::uint32_t point_count, std::span<const PointGrid> grids) {
  for (auto& p : pools_) p->prepare_on_grids(point_count, grids);
}

void LinkSet::parameters_changed() {
  for (auto& p : pools_) p->parameters_changed();
}

}  // namespace maille
