#ifndef EULERSPLAT_SOLVERS_OPTIM_SPARSE_ADAM_H_
#define EULERSPLAT_SOLVERS_OPTIM_SPARSE_ADAM_H_

#include <cstdint>
#include <vector>

#include "solvers/optim/adam.h"

namespace es {

// Adam over one parameter block whose gradient is zero almost everywhere,
// such as a field's triplane (a point touches four texels per plane): the
// same updates as AdamUpdate, value for value, but a step touches only the
// chunks of values that have a non-zero gradient now or non-zero moments
// from before, and hands back the gradient buffer zeroed, so the caller's
// buffer never needs a full clear, scan or update.
//
// Use per step: the block's gradient is accumulated into a buffer that is
// all zero; ScanGradient checks it for non-finite values and notes the
// chunks it touches; then either Step (which re-zeroes those chunks) or,
// to drop the step, ClearGradient. Where every producer of the gradient
// flags the chunks it writes (FieldGradients::triplane_chunks) into
// chunk_flags(), ScanFlagged replaces ScanGradient and reads only those
// chunks instead of the whole block. Chunks are kGradientChunk values
// (core/fields/gradient_chunks.h).
class SparseAdam {
 public:
  explicit SparseAdam(int size = 0, const AdamOptions& options = {});

  int size() const { return static_cast<int>(m_.size()); }
  const std::vector<double>& m() const { return m_; }
  const std::vector<double>& v() const { return v_; }
  // Moments from a checkpoint (size() values each).
  void Restore(std::vector<double> m, std::vector<double> v);

  // False if any of the size() values of grad is not finite.
  bool ScanGradient(const double* grad);
  // One flag per chunk for the gradient's producers to set where they
  // write; all zero again after Step or ClearGradient.
  char* chunk_flags() { return touched_.data(); }
  // ScanGradient for a gradient that is zero outside the chunks flagged in
  // chunk_flags(): reads only those. False if any value there is not
  // finite.
  bool ScanFlagged(const double* grad);
  // Zeroes the chunks of grad the last scan found non-zero.
  void ClearGradient(double* grad);
  // One Adam step t with rate lr on x (size() values) from the last
  // ScanGradient's gradient, which it zeroes. Returns false if a value it
  // changed is not finite (those it did not change are as before).
  bool Step(int64_t t, double lr, double* grad, double* x);

 private:
  // Notes whether chunk c of `grad` is touched; returns whether it is finite.
  bool ScanChunk(const double* grad, int c);

  AdamOptions options_;
  std::vector<double> m_, v_;
  std::vector<char> live_;     // per chunk: its moments may be non-zero
  // Per chunk: non-zero gradient at the scan (before ScanFlagged: flagged
  // by a producer).
  std::vector<char> touched_;
  std::vector<int> active_;    // chunks Step updates
  std::vector<int> flagged_;   // ScanFlagged's flagged chunks
};

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_OPTIM_SPARSE_ADAM_H_
