#include "maille/profile.hpp"

namespace maille {

int Profile::stage(const std::string& name) {
  for (std::size_t i = 0; i < stages_.size(); ++i)
    if (stages_[i].name == name) return static_cast<int>(i);
  stages_.push_back({name});
  return static_cast<int>(stages_.size()) - 1;
}

int Profile::counter(const std::string& name) {
  for (std::size_t i = 0; i < counters_.size(); ++i)
    if (counters_[i].name == name) return static_cast<int>(i);
  counters_.push_back({name});
  return static_cast<int>(counters_.size()) - 1;
}

int Profile::gauge(const std::string& name) {
  for (std::size_t i = 0; i < gauges_.size(); ++i)
    if (gauges_[i].name == name) return static_cast<int>(i);
  gauges_.push_back({name});
  return static_cast<int>(gauges_.size()) - 1;
}

void Profile::add_time(int stage, double ns) {
  stages_[stage].last_ns += ns;
  stages_[stage].total_ns += ns;
}

void Profile::set_count(int counter, std::uint64_t value) {
  counters_[counter].last = value;
  counters_[counter].total += value;
}

void Profile::add_count(int counter, std::uint64_t value) {
  counters_[counter].last += value;
  counters_[counter].total += value;
}

void Profile::begin_step() {
  ++steps_;
  for (auto& s : stages_) s.last_ns = 0;
  for (auto& c : counters_) c.last = 0;
}

double Profile::total_ns() const {
  double t = 0;
  for (const auto& s : stages_) t += s.total_ns;
  return t;
}

}  // namespace maille
