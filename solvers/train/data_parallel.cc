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

void CheckResumedBatch(int checkpoint_batch, int batch_frames,
                       const std::string& path) {
  if (checkpoint_batch == batch_frames) return;
  throw InputError(path + ": written by a run with --batch_frames " +
                   std::to_string(checkpoint_batch) + ", this one has " +
                   std::to_string(batch_frames) + "; resume with "
                   "--batch_frames " + std::to_string(checkpoint_batch) +
                   " (eulersplat: the same --ranks or --batch_frames), or "
                   "start over without the checkpoint");
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
  if (comm->size() == 1) return;  // the sum of one rank
  const size_t n = data_.size();
  const size_t chunks = (n + kSumChunk - 1) / kSumChunk;
  nonzero_.assign(chunks, 0);
  for (size_t c = 0; c < chunks; ++c) {
    const size_t end = std::min(n, (c + 1) * kSumChunk);
    // NaN != 0 too: a rank's non-finite value reaches every rank.
    for (size_t i = c * kSumChunk; i < end && !nonzero_[c]; ++i)
      nonzero_[c] = data_[i] != 0.0;
  }
  comm->AllreduceMax(nonzero_.data(), chunks);
  packed_.clear();
  for (size_t c = 0; c < chunks; ++c) {
    if (!nonzero_[c]) continue;
    const size_t end = std::min(n, (c + 1) * kSumChunk);
    packed_.insert(packed_.end(), data_.begin() + c * kSumChunk,
                   data_.begin() + end);
  }
  comm->AllreduceSum(packed_.data(), packed_.size());
  size_t at = 0;
  for (size_t c = 0; c < chunks; ++c) {
    if (!nonzero_[c]) continue;
    const size_t end = std::min(n, (c + 1) * kSumChunk);
    std::copy_n(packed_.begin() + at, end - c * kSumChunk,
                data_.begin() + c * kSumChunk);
    at += end - c * kSumChunk;
  }
  sent_bytes_ += chunks + sizeof(double) * packed_.size();
  ++reductions_;
}

void PackedSum::Divide(int segment, double divisor) {
  double* out = at(segment);
  const size_t n = size(segment);
  for (size_t i = 0; i < n; ++i) out[i] /= divisor;
}

}  // namespace es
