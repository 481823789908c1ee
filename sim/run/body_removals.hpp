// Bodies taken out of the scene during the run ([[body]] remove_at, s).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "run/controller.hpp"

namespace dem2d {

class BodyRemovals final : public Controller {
 public:
  explicit BodyRemovals(const Scene& scene);
  std::string name() const override { return "body_removals"; }
  std::int64_t next_step() const override { return next_ < at_.size() ? at_[next_].first : kNever; }
  std::string act(System& sys) override;
  void save(const ControllerState& out) override { out.put("next", static_cast<std::int64_t>(next_)); }
  void restore(const ControllerState& in) override { next_ = static_cast<std::size_t>(in.get_int("next")); }

 private:
  std::vector<std::pair<std::int64_t, std::size_t>> at_;  // (step, body), by step
  std::size_t next_ = 0;
};

}  // namespace dem2d
