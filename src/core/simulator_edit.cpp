// Edits between steps. A model is prepared once (pools reordered and grouped, faces coloured)
// and the simulator sizes buffers from it, so a structural edit must rebuild all of that; a
// parameter edit must not pay for it. The two entry points make the difference explicit, and a
// structural change sneaked into a parameter edit is detected rather than left stale.
#include <algorithm>
#include <stdexcept>

#include "maille/simulator.hpp"

namespace maille {

namespace {

// What a parameter edit must leave unchanged.
struct Structure {
  std::size_t points = 0, faces = 0, drives = 0, stages = 0;
  std::vector<std::size_t> pools;
  bool operator==(const Structure&) const = default;
};

Structure structure_of(const Model& m) {
  Structure s{m.points.size(), m.surface.triangles.size(), m.drives.size(), m.stages.size(), {}};
  for (const auto& p : m.links.pools()) s.pools.push_back(p->size());
  return s;
}

}  // namespace

// Both edits are made on the live model with a copy kept: when the result is not a valid model
// (check_model: structure and parameters) or one the scheme or a stage refuses, the simulator
// takes the copy back, so model and state are exactly as they were, and throws
// std::invalid_argument. The copy costs a pass over the model, far less than re-preparing it.
void Simulator::edit_parameters(const std::function<void(Model&)>& edit) {
  sync_host();
  host_ahead_ = true;  // the device copy of the model is reloaded before the next step
  const Structure before = structure_of(model_);
  Model previous = model_;
  edit(model_);
  if (structure_of(model_) != before) return apply_or_restore(std::move(previous));
  if (const std::string why = check_model(model_); !why.empty()) {
    model_ = std::move(previous);
    model_structure_changed();  // the pools are the copy's: the schedule points into them anew
    throw std::invalid_argument("edit refused: " + why);
  }
  model_.links.parameters_changed();  // rows of equal records, for the structured kernel
  restimate_stability();
}

void Simulator::edit_model(const std::function<void(Model&)>& edit) {
  sync_host();
  host_ahead_ = true;
  Model previous = model_;
  edit(model_);
  apply_or_restore(std::move(previous));
}

// After a structural edit of model_ (previous: the model before it): checks, re-prepares and
// rebuilds, or restores previous and the state and rethrows.
void Simulator::apply_or_restore(Model previous) {
  State previous_state = state_;
  try {
    if (const std::string why = check_model(model_); !why.empty())
      throw std::invalid_argument("edit refused: " + why);
    model_structure_changed();
  } catch (...) {
    model_ = std::move(previous);
    model_structure_changed();
    state_ = std::move(previous_state);
    throw;
  }
}

// Re-prepares the pools, resizes the state (new points start at their initial position and
// velocity; the scheme's history is kept), rebuilds the scheme and the stages.
void Simulator::model_structure_changed() {
  model_.prepare();
  const std::size_t n = model_.points.size();
  if (n != state_.size()) {
    State s(n);
    const std::size_t keep = std::min(n, state_.size());
    std::copy_n(state_.x().begin(), keep, s.x().begin());
    std::copy_n(state_.v().begin(), keep, s.v().begin());
    for (std::size_t i = keep; i < n; ++i) {
      s.x()[i] = model_.points.initial_position[i];
      s.v()[i] = model_.points.initial_velocity[i];
    }
    s.time = state_.time;
    s.step = state_.step;
    s.history = state_.history;
    s.stage_memory = state_.stage_memory;
    state_ = std::move(s);
    scratch_velocity_.assign(n, Vec3{});
  }
  // Stages made from the model are made again; stages added by code are told.
  std::erase_if(stages_, [](const Installed& st) { return st.from_model; });
  for (auto& st : stages_) st.stage->model_changed(model_);
  build_integrator(settings_.integrator);  // fresh buffers sized for the new model
  install_model_stages();
  energy_scale_ = energy_scale();
}

}  // namespace maille
