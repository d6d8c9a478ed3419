#include "core/fields/field_gradient_buffer.h"

#include <algorithm>

#include <glog/logging.h>

#include "core/fields/gradient_chunks.h"

namespace es {
namespace {

// Below this many triplane chunks a parallel region costs more than it
// saves.
constexpr int kMinParallelChunks = 256;

}  // namespace

void FieldGradientBuffer::Resize(int triplane_params, int mlp_params) {
  if (static_cast<int>(triplane_.size()) != triplane_params) {
    triplane_.assign(triplane_params, 0.0);
    chunks_.assign(NumGradientChunks(triplane_params), 0);
  }
  if (static_cast<int>(mlp_.size()) != mlp_params) {
    mlp_.assign(mlp_params, 0.0);
    mlp_written_ = false;
  }
}

FieldGradients FieldGradientBuffer::Gradients(const FieldGradients& like) {
  FieldGradients g;
  if (like.triplane != nullptr) {
    g.triplane = triplane_.data();
    g.triplane_chunks = chunks_.data();
  }
  if (like.mlp != nullptr) {
    g.mlp = mlp_.data();
    mlp_written_ = true;
  }
  return g;
}

void AddAndClearGradients(const std::vector<FieldGradientBuffer*>& buffers,
                          const FieldGradients& out) {
  if (buffers.empty()) return;
  const FieldGradientBuffer& first = *buffers.front();
  for (const FieldGradientBuffer* b : buffers) {
    CHECK_EQ(b->triplane_.size(), first.triplane_.size());
    CHECK_EQ(b->mlp_.size(), first.mlp_.size());
  }
  if (out.mlp != nullptr) {
    for (FieldGradientBuffer* b : buffers) {
      if (!b->mlp_written_) continue;
      for (size_t i = 0; i < b->mlp_.size(); ++i) {
        out.mlp[i] += b->mlp_[i];
        b->mlp_[i] = 0.0;
      }
      b->mlp_written_ = false;
    }
  }
  if (out.triplane == nullptr) return;
  const size_t size = first.triplane_.size();
  const int chunks = NumGradientChunks(size);
#pragma omp parallel for schedule(static) if (chunks >= kMinParallelChunks)
  for (int c = 0; c < chunks; ++c) {
    const size_t begin = static_cast<size_t>(c) * kGradientChunk;
    const size_t end = std::min(size, begin + kGradientChunk);
    for (FieldGradientBuffer* b : buffers) {
      if (!b->chunks_[c]) continue;
      b->chunks_[c] = 0;
      double* src = b->triplane_.data();
      for (size_t i = begin; i < end; ++i) {
        out.triplane[i] += src[i];
        src[i] = 0.0;
      }
      if (out.triplane_chunks != nullptr) out.triplane_chunks[c] = 1;
    }
  }
}

}  // namespace es
