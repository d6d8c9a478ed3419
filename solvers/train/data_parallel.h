#ifndef EULERSPLAT_SOLVERS_TRAIN_DATA_PARALLEL_H_
#define EULERSPLAT_SOLVERS_TRAIN_DATA_PARALLEL_H_

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/communicator.h"
#include "solvers/optim/frame_sampler.h"

namespace es {

// Data-parallel batches, what the Stage 1 and Stage 3 trainers share when
// `batch_frames` > 1: every rank draws the same B frames from its sampler
// (same seed, same draws), renders its share (frame k of the batch on rank
// k mod size), the ranks' sums of gradients are added with one allreduce
// and divided by B, and every rank steps Adam on the same mean.

// The next `batch_frames` frames of the sampler.
std::vector<int> DrawBatch(FrameSampler* sampler, int batch_frames);

// Whether this rank renders frame k (0-based) of a batch.
inline bool RendersBatchFrame(const Communicator& comm, int k) {
  return k % comm.size() == comm.rank();
}

// The batch settings a stage checks before any work: `batch_frames` >= 1,
// and >= the ranks (a rank with no frame would only wait). Throws
// InputError naming `flag`.
void CheckBatchFrames(int batch_frames, const Communicator& comm,
                      const std::string& flag = "--batch_frames");

// Values per chunk of PackedSum's sparse allreduce: a flag per 512 bytes.
constexpr size_t kSumChunk = 64;

// A resume from `path`, written by a run with `checkpoint_batch` frames
// per iteration, by one with `batch_frames`: throws InputError unless
// they are equal, since another batch draws other frames and would not
// continue the same run.
void CheckResumedBatch(int checkpoint_batch, int batch_frames,
                       const std::string& path);

// Several arrays (segments) packed one after the other, so that one
// allreduce sums them all over the ranks.
class PackedSum {
 public:
  // Segments of these sizes, all zero.
  void Reset(const std::vector<size_t>& sizes);

  int segments() const { return static_cast<int>(offsets_.size()) - 1; }
  size_t size(int segment) const {
    return offsets_[segment + 1] - offsets_[segment];
  }
  double* at(int segment) { return data_.data() + offsets_[segment]; }
  const double* at(int segment) const {
    return data_.data() + offsets_[segment];
  }
  // at(segment)[i] += values[i].
  void Add(int segment, const double* values);
  // Every segment summed over the ranks. Only the chunks of kSumChunk
  // values that some rank holds non-zero are sent: a small allreduce of
  // one flag per chunk, then one AllreduceSum of those chunks packed
  // together (a batch leaves most of a field's triplane untouched). The
  // values are those of a sum of everything: a chunk no rank flags is zero
  // on every rank. With --profile, the wait for the slowest rank (a
  // barrier) is timed apart from the sum itself.
  void AllreduceSum(Communicator* comm);
  // Bytes a rank sent per AllreduceSum on average (flags and chunks); in
  // one process, which sends nothing, the whole buffer's.
  size_t bytes_per_reduction() const {
    return reductions_ > 0 ? static_cast<size_t>(sent_bytes_ / reductions_)
                           : sizeof(double) * data_.size();
  }
  // at(segment)[i] /= divisor.
  void Divide(int segment, double divisor);

  const std::vector<double>& data() const { return data_; }

 private:
  std::vector<size_t> offsets_ = {0};
  std::vector<double> data_;
  std::vector<unsigned char> nonzero_;  // per chunk, over the ranks
  std::vector<double> packed_;          // the flagged chunks
  double sent_bytes_ = 0;
  int64_t reductions_ = 0;
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_TRAIN_DATA_PARALLEL_H_
