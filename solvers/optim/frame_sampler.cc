#include "solvers/optim/frame_sampler.h"

#include <glog/logging.h>

#include <algorithm>

#include "core/base/input_error.h"
#include "core/base/rng_state.h"

namespace es {

FrameSampler::FrameSampler(std::vector<int> frames, uint64_t seed)
    : frames_(std::move(frames)), rng_(seed) {
  CHECK(!frames_.empty()) << "no frames to sample";
}

int FrameSampler::Next() {
  if (position_ >= static_cast<int>(order_.size())) {
    order_ = frames_;
    // Our own Fisher-Yates: std::shuffle's algorithm is unspecified, and a
    // checkpoint must replay identically across standard libraries.
    for (int i = static_cast<int>(order_.size()) - 1; i > 0; --i) {
      const int j = static_cast<int>(rng_() % static_cast<uint64_t>(i + 1));
      std::swap(order_[i], order_[j]);
    }
    position_ = 0;
  }
  return order_[position_++];
}

FrameSampler::State FrameSampler::state() const {
  State s;
  s.rng = RngState(rng_);
  s.order = order_;
  s.position = position_;
  return s;
}

void FrameSampler::Restore(const State& s) {
  // The state comes from a file: a checkpoint of another scene or a corrupt
  // one is an input error, not a crash.
  std::mt19937_64 rng;
  if (!RestoreRngState(s.rng, &rng))
    throw InputError("checkpoint: bad frame sampler RNG state");
  if (s.position < 0 || s.position > static_cast<int>(s.order.size()))
    throw InputError("checkpoint: frame sampler position out of range");
  std::vector<int> sorted_order = s.order, sorted_frames = frames_;
  std::sort(sorted_order.begin(), sorted_order.end());
  std::sort(sorted_frames.begin(), sorted_frames.end());
  if (!s.order.empty() && sorted_order != sorted_frames)
    throw InputError(
        "checkpoint: its frame order is not a permutation of this run's "
        "training frames (another scene or split?)");
  rng_ = rng;
  order_ = s.order;
  position_ = s.position;
}

}  // namespace es
