// What the obstacle stages whose contacts enter implicit solves as PointContacts (the geometric
// and conditional methods) share: apply() adds the contact forces at the step's start (explicit
// schemes); under an implicit scheme find_contacts() puts the stage into the step's contact set
// (contact_set.hpp: the solver evaluates it at every iterate) and only counts. Both go through
// the stage's one scan of its points.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "maille/contact_set.hpp"
#include "maille/profile.hpp"
#include "maille/stage.hpp"
#include "maille/state.hpp"

namespace maille {

class PointContactStage : public Stage, public PointContacts {
 public:
  void apply(const Model&, State& s, const StageContext& ctx) final { scan(s, ctx, s.f().data()); }
  ContactKinds contacts_found() const final { return ContactKinds::obstacles; }
  void find_contacts(const Model&, State& s, const StageContext& ctx, ContactSet& set) final {
    scan(s, ctx, nullptr);
    set.add(*this);
  }

 protected:
  // The contacts at (x_n, t_n): their forces into f (when not null), then count().
  virtual void scan(const State& s, const StageContext& ctx, Vec3* f) = 0;
  // The counters obstacle_<name>_contacts and obstacle_<name>_depth (m, the deepest).
  void count(const StageContext& ctx, const std::string& obstacle, std::uint64_t contacts,
             Real deepest) {
    if (!ctx.profile) return;
    if (columns_.empty())
      columns_ = {{"obstacle_" + obstacle + "_contacts"},
                  {"obstacle_" + obstacle + "_depth", true}};
    columns_.set(*ctx.profile, {contacts, deepest});
  }

 private:
  ProfileColumns columns_;
};

}  // namespace maille
