#include "solvers/train/data_parallel.h"

#include <glog/logging.h>

#include <algorithm>

#include "core/base/input_error.h"
#include "core/base/stage_profile.h"

namespace es {

std::vector<int> DrawBatch(FrameSampler* sampler, int batch_frames) {
  CHECK_GE(batch_frames, 1);
  std::vector<int> batch(batch_frames);
  for (int& frame : batch) frame = sampler->Next();
  return batch;
}

void CheckBatchFrames(int batch_frames, const Communicator& comm,
                      const std::string& flag) {
  if (batch_frames < 1) {
    throw InputError(flag + " must be >= 1, got " +
                     std::to_string(batch_frames));
  }
  if (batch_frames < comm.size()) {
    throw InputError(flag + " " + std::to_string(batch_frames) + " < " +
                     std::to_string(comm.size()) +
                     " ranks: each rank renders at least one frame of a "
                     "batch (pass " + flag + " " +
                     std::to_string(comm.size()) + " or more)");
  }
}

void PackedSum::Reset(const std::vector<size_t>& sizes) {
  offsets_.assign(1, 0);
  for (size_t s : sizes) offsets_.push_back(offsets_.back() + s);
  data_.assign(offsets_.back(), 0.0);
}

void PackedSum::Add(int segment, const double* values) {
  double* out = at(segment);
  const size_t n = size(segment);
  for (size_t i = 0; i < n; ++i) out[i] += values[i];
}

void PackedSum::AllreduceSum(Communicator* comm) {
  if (comm->size() > 1 && StageProfile::On()) {
    ScopedStage wait_timer(Stage::kRankWait);
    comm->Barrier();
  }
  ScopedStage timer(Stage::kAllreduce);
  comm->AllreduceSum(data_.data(), data_.size());
}

void PackedSum::Divide(int segment, double divisor) {
  double* out = at(segment);
  const size_t n = size(segment);
  for (size_t i = 0; i < n; ++i) out[i] /= divisor;
}

}  // namespace es
