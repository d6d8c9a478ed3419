#ifndef EULERSPLAT_SOLVERS_OPTIM_FRAME_SAMPLER_H_
#define EULERSPLAT_SOLVERS_OPTIM_FRAME_SAMPLER_H_

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace es {

// Draws training frames in shuffled epochs: every frame once per epoch, a
// fresh seeded permutation each epoch. The state round-trips exactly so a
// resumed run draws the same sequence.
class FrameSampler {
 public:
  struct State {
    std::string rng;         // std::mt19937_64 in its text form
    std::vector<int> order;  // the current epoch's permutation
    int position = 0;        // next index into order
  };

  FrameSampler(std::vector<int> frames, uint64_t seed);

  int Next();

  State state() const;
  // Restores a state saved from a sampler over the same frames.
  void Restore(const State& state);

 private:
  std::vector<int> frames_;
  std::mt19937_64 rng_;
  std::vector<int> order_;
  int position_ = 0;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_OPTIM_FRAME_SAMPLER_H_
