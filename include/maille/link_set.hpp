// The model's links: one typed pool per link kind.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "maille/link_pool.hpp"

namespace maille {

// The model's links: one pool per kind, in the order kinds were first used.
class LinkSet {
 public:
  LinkSet() = default;
  LinkSet(const LinkSet& other);
  LinkSet& operator=(const LinkSet& other);
  LinkSet(LinkSet&&) noexcept = default;
  LinkSet& operator=(LinkSet&&) noexcept = default;

  template <LinkKind K>
  LinkPool<K>& pool() {
    for (auto& p : pools_)
      if (auto* typed = dynamic_cast<LinkPool<K>*>(p.get())) return *typed;
    pools_.push_back(std::make_unique<LinkPool<K>>());
    return static_cast<LinkPool<K>&>(*pools_.back());
  }
  LinkPoolBase* find(std::string_view keyword);
  const LinkPoolBase* find(std::string_view keyword) const;
  LinkPoolBase& adopt(std::unique_ptr<LinkPoolBase> pool);

  std::span<const std::unique_ptr<LinkPoolBase>> pools() const { return pools_; }
  std::size_t total() const;
  // Prepares every pool (LinkPoolBase::prepare_on_grids): links on the regular grids run in the
  // structured kernel where their kind opts in.
  void prepare(std::uint32_t point_count, std::span<const PointGrid> grids = {});
  // Parameters were edited in place: tells every pool (LinkPoolBase::parameters_changed).
  void parameters_changed();

 private:
  std::vector<std::unique_ptr<LinkPoolBase>> pools_;
};

}  // namespace maille
